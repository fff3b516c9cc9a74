# Everything about a frame that can be judged before Blender renders it, checked by the
# render_init handler (and again for each frame written): the camera can be modelled
# (camera_fov.py), Blender will write what wavecam reads, the wavecam command is there, and
# every setting can be imaged. Each refusal names the setting as the panel shows it and the
# range expected. The ranges are the command's own (wavecam apply refuses the same values):
# a pinhole from the longest wavelength to the film's width (scalar diffraction through a hole
# smaller than the light means nothing; one wider than the film images nothing).
import math
import re

from .camera_settings import MIN_FILM_DISTANCE_MM
from .preferences import wavecam_command

VISIBLE_NM = (400.0, 700.0)  # the range a wavelength count samples
LIGHT_NM = (100.0, 10000.0)  # what a listed wavelength may be: light, not X-rays or radio
_NM_PER_UNIT = {"nm": 1.0, "um": 1e3, "µm": 1e3, "mm": 1e6}


class SettingError(Exception):
    pass


def wavelengths_nm(settings):
    """The listed wavelengths in nm (increasing, light), or the count's range; SettingError else."""
    if not settings.use_wavelength_list:
        return list(VISIBLE_NM)
    text = settings.wavelength_list.replace(" ", "")
    values = []
    for item in text.split(","):
        m = re.fullmatch(r"([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)(nm|um|µm|mm)", item)
        if not m:
            raise SettingError(f"Wavelength list: '{item}' is not a wavelength; expected wavelengths with a unit, "
                               "e.g. 450nm,550nm,650nm")
        nm = float(m.group(1)) * _NM_PER_UNIT[m.group(2)]
        if not LIGHT_NM[0] <= nm <= LIGHT_NM[1]:
            raise SettingError(f"Wavelength list: {item} is not light; expected wavelengths from 100nm to 10um")
        if values and nm <= values[-1]:
            raise SettingError(f"Wavelength list: {item} follows {values[-1]:g}nm; expected an increasing list")
        values.append(nm)
    return values


def check_settings(camera, fov_degrees):
    """The panel's values for `camera` (bpy Camera data) at a horizontal field of view, each as
    typed: a value beyond its range is refused, never clamped."""
    w = camera.wavecam
    if not w.use_wavelength_list and not 1 <= w.wavelength_count <= 1000:
        raise SettingError(f"Wavelengths {w.wavelength_count}: expected a count from 1 to 1000")
    if w.method == 'random-phase' and not w.auto_runs and not 1 <= w.runs <= 100000:
        raise SettingError(f"Runs {w.runs}: expected a count from 1 to 100000")
    film_mm = w.film_distance_mm(camera)
    if not film_mm >= MIN_FILM_DISTANCE_MM:
        raise SettingError(f"Film distance {film_mm:g} mm: the film must lie behind the pinhole; expected "
                           f"{MIN_FILM_DISTANCE_MM:g} mm or more")
    if w.method != 'convolution':
        typed = w.get("max_terms_typed")
        if typed:
            raise SettingError(f"Max terms '{typed}' is not a count of terms; expected a number of 1 or more, "
                               "e.g. 4e12")
        if w.device == 'gpu' and w.summation == 'nufft':
            raise SettingError("Device GPU with Summation NUFFT: the NUFFTs have no GPU evaluator; expected "
                               "Summation Auto, Direct or Kernel on the GPU, or Device CPU")
    longest_nm = max(wavelengths_nm(w))
    pinhole_mm = w.pinhole_mm(camera)
    film_width_mm = 2 * film_mm * math.tan(math.radians(fov_degrees) / 2)
    if not longest_nm * 1e-6 <= pinhole_mm <= film_width_mm:
        why = (f"smaller than the longest wavelength ({longest_nm:g} nm): no image forms"
               if pinhole_mm < longest_nm * 1e-6 else
               f"wider than the film ({film_width_mm:.4g} mm across at {film_mm:g} mm and {fov_degrees:.4g} deg)")
        raise SettingError(f"Pinhole {pinhole_mm:g} mm is {why}; expected {longest_nm * 1e-6:g} mm to "
                           f"{film_width_mm:.4g} mm")


def check_output(scene):
    """Blender will write an OpenEXR with a depth pass, of one view layer."""
    image = scene.render.image_settings
    if image.file_format not in {'OPEN_EXR', 'OPEN_EXR_MULTILAYER'}:
        name = image.bl_rna.properties['file_format'].enum_items[image.file_format].name
        raise SettingError(f"the frame is saved as {name}; wavecam needs OpenEXR "
                           "(Output > Output > File Format: OpenEXR MultiLayer)")
    if image.file_format == 'OPEN_EXR' and not image.use_zbuffer:
        raise SettingError("the OpenEXR output has no depth: tick Z Buffer, or use OpenEXR MultiLayer")
    layers = [layer for layer in scene.view_layers if layer.use]
    if image.file_format == 'OPEN_EXR_MULTILAYER':
        if len(layers) != 1:
            raise SettingError(f"{len(layers)} view layers render into one file; wavecam diffracts one: "
                               "untick 'Use for Rendering' on all but one")
        if not layers[0].use_pass_z:
            raise SettingError(f"view layer '{layers[0].name}' has no Z pass (View Layer > Passes > Z)")


def check_command():
    if not wavecam_command():
        raise SettingError("the wavecam command was not found: install wavecam, or set its path in "
                           "Preferences > Add-ons > wavecam")


def check_frame(scene, rendered):
    """All of the above for a frame whose camera is `rendered` (a RenderedCamera)."""
    if rendered.fov_error:
        raise SettingError(rendered.fov_error)
    if rendered.settings_error:
        raise SettingError(rendered.settings_error)
    check_output(scene)
    check_command()
