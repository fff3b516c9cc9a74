#!/usr/bin/env bash
# The main job: installs dependencies, builds wavecam, renders the default scene with the test
# tracer (an ideal pinhole), diffracts it through three pinholes at f = 50 mm - too small,
# Rayleigh's optimum 1.9 sqrt(f lambda), too large - and writes out/contact_sheet.png, which
# shows at a glance that the optimum is the sharpest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
mkdir -p out
wavecam=build/plugin/wavecam
./build/test_scenes/wavecam-trace test_scenes/scenes/default.toml out/scene.exr --width 512 --height 512

for pinhole in 0.08mm 0.315mm 1.26mm; do
  "$wavecam" apply out/scene.exr -o "out/pinhole_${pinhole}.exr" --pinhole "$pinhole" --film-distance 50mm \
    --wavelengths 16
done

# Contact sheet through the shipped config's sRGB display view: full frames on top, the
# centre 128 x 128 enlarged 4x below, each labelled.
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
oiiotool --colorconfig ocio_configs/wavecam.ocio \
  out/scene.exr --ch R,G,B --ociodisplay sRGB Standard --text:x=10:y=30:size=24:color=1,1,0.2:font=$font "ideal pinhole (render), f = 50 mm" \
  out/pinhole_0.08mm.exr --ch R,G,B --ociodisplay sRGB Standard --text:x=10:y=30:size=24:color=1,1,0.2:font=$font "0.08 mm: too small (diffraction)" \
  out/pinhole_0.315mm.exr --ch R,G,B --ociodisplay sRGB Standard --text:x=10:y=30:size=24:color=1,1,0.2:font=$font "0.315 mm: optimum 1.9 sqrt(f lambda)" \
  out/pinhole_1.26mm.exr --ch R,G,B --ociodisplay sRGB Standard --text:x=10:y=30:size=24:color=1,1,0.2:font=$font "1.26 mm: too large (geometric)" \
  out/scene.exr --ch R,G,B --ociodisplay sRGB Standard --cut 128x128+192+192 --resize:filter=box 512x512 --text:x=10:y=30:size=24:color=1,1,0.2:font=$font "centre of the frame, 4x" \
  out/pinhole_0.08mm.exr --ch R,G,B --ociodisplay sRGB Standard --cut 128x128+192+192 --resize:filter=box 512x512 \
  out/pinhole_0.315mm.exr --ch R,G,B --ociodisplay sRGB Standard --cut 128x128+192+192 --resize:filter=box 512x512 \
  out/pinhole_1.26mm.exr --ch R,G,B --ociodisplay sRGB Standard --cut 128x128+192+192 --resize:filter=box 512x512 \
  --mosaic:pad=4 4x2 -d uint8 -o out/contact_sheet.png
# A star field over the same 60 deg frame through the too-small pinhole: each star's image is its
# PSF at its own field, 1/cos^3 wider radially and 1/cos tangentially off axis, the centre's the
# on-axis Airy pattern. The stars at the centre, half way to the corner and in the corner,
# enlarged 8x and exposed 16x brighter.
/usr/bin/python3 test_scenes/star_field.py out/stars.exr --size 512 --fov 60  # Debian's (OIIO, numpy)
"$wavecam" apply out/stars.exr -o out/stars_0.08mm.exr --pinhole 0.08mm --film-distance 50mm --wavelengths 16
crop() {  # crop X Y LABEL: 40x40 round star (X, Y), enlarged 8x
  echo out/stars_0.08mm.exr --ch R,G,B --mulc 16 --ociodisplay sRGB Standard --cut "40x40+$(($1 - 20))+$(($2 - 20))" \
    --resize:filter=box 320x320 --text:x=8:y=24:size=18:color=1,1,0.2:font=$font "$3"
}
oiiotool --colorconfig ocio_configs/wavecam.ocio $(crop 256 256 centre) $(crop 160 160 halfway) \
  $(crop 32 32 corner) --mosaic:pad=4 3x1 -d uint8 -o out/star_field.png
# The paper's figure: PSFs over pinhole diameters, spot size against diameter, the optimum.
"$wavecam" sweep --film-distance 50mm --wavelength 550nm -o out/sweep
echo "wrote out/scene.exr, out/pinhole_*.exr, out/contact_sheet.png, out/star_field.png, out/sweep*"
