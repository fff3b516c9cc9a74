# The benchmarks' frame, sourced by their scripts: frame W H FOV OUT writes a W x H radiance +
# depth EXR at FOV degrees, uniform noise times a checker of $checker pixels (64 unless set),
# depth from 0.3 m (top) to 20 m (bottom).
frame() {
  local square=${checker:-64}
  oiiotool --pattern noise:type=uniform:min=0:max=1 "$1x$2" 3 --chnames R,G,B \
           --pattern checker:width=$square:height=$square:color1=0.2,0.2,0.2:color2=1,1,1 "$1x$2" 3 --mul \
           --pattern fill:top=0.3:bottom=20 "$1x$2" 1 --chnames Z --chappend \
           --attrib wavecam.fov "$3" -d float -o "$4"
}
