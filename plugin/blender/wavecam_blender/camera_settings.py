# The wavecam settings a camera carries (camera.data.wavecam). The pinhole and film distance
# follow the camera's lens unless set by hand.
#
# No field has a hard limit: a typed value is kept as typed, and whether it can be imaged (a
# pinhole between the longest wavelength and the film's width, a film distance of 0.1 mm or more,
# 1-1000 wavelengths, 1-100000 runs: the command's own ranges) is checked before each render
# (settings_check.py) and refused with a message naming the setting and the value typed, never
# clamped. Soft limits are the useful range the sliders drag over.
import math

import bpy

from . import pinhole_design, reports


def _ui_name(struct, prop):
    """An enum's value as Blender's UI names it ('OPEN_EXR_MULTILAYER' -> 'OpenEXR MultiLayer')."""
    value = getattr(struct, prop)
    return struct.bl_rna.properties[prop].enum_items[value].name


def _turn_on_depth_output(settings, context):
    """Enabling wavecam makes Blender write what wavecam reads: an OpenEXR with a depth pass.
    What it changes is said once, in the Info log."""
    scene = context.scene if context else None
    if not settings.enabled or scene is None:
        return
    changed = []
    for layer in scene.view_layers:
        if not layer.use_pass_z:
            layer.use_pass_z = True
            changed.append(f"the Z pass of view layer '{layer.name}' turned on")
    image = scene.render.image_settings
    if image.file_format not in {'OPEN_EXR', 'OPEN_EXR_MULTILAYER'}:
        was = _ui_name(image, "file_format")
        image.file_format = 'OPEN_EXR_MULTILAYER'
        image.color_depth = '32'
        changed.append(f"the output's File Format {was} changed to OpenEXR MultiLayer, Float (Full)")
    if image.file_format == 'OPEN_EXR' and not image.use_zbuffer:
        image.use_zbuffer = True
        changed.append("the OpenEXR output's Z Buffer turned on")
    if changed:
        reports.info("on: " + "; ".join(changed) + " (wavecam reads depth from OpenEXR)")


MIN_FILM_DISTANCE_MM = 0.1  # the command's own limit (wavecam apply --film-distance)
DEFAULT_MAX_TERMS = 4e12


def _max_terms_text(self):
    """Max terms as a person writes a count: 4e12, not 3999999983616.000 (Blender shows floats in
    full); what was typed, where it was no count."""
    return self.get("max_terms_typed") or f"{self.max_terms:.4g}".replace("e+", "e")


def _set_max_terms_text(self, text):
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if math.isfinite(value) and value >= 1:
        self.max_terms = value
        self["max_terms_typed"] = ""
    else:  # kept as typed: the render refuses it by name (settings_check.py)
        self["max_terms_typed"] = text

# The numbers are what a .blend file stores for an enum (not the identifiers): files saved when
# these were called 'fast' (0) and 'exact' (1) load as convolution and random-phase, and a summation
# saved as 'psf' (3) as kernel.
METHODS = [
    ('convolution', "Convolution", "PSF grid and FFT convolution (the default)", 0),
    ('random-phase', "Random phase", "The seed paper's random-phase sum, averaged over runs (slow; small frames)", 1),
    ('incoherent', "Incoherent", "Every source propagated alone: the limit of infinitely many runs (very slow)", 2),
]

SUMMATIONS = [
    ('auto', "Auto", "The point sums through the cheaper of their two evaluators (the default)", 0),
    ('direct', "Direct", "The point sums term by term: the reference (slowest)", 1),
    ('nufft', "NUFFT", "The point sums through NUFFTs over the pinhole lattice", 2),
    ('kernel', "Kernel", "Each run as a convolution with amplitude kernels from the point sums: within a few percent of "
     "them, far cheaper", 3),
]
DEVICES = [
    ('cpu', "CPU", "The processor (the default)", 0),
    ('gpu', "GPU", "A Vulkan device, a discrete GPU first, running every sum; none is an error, and so is "
     "Summation NUFFT (no GPU evaluator). Where there is no GPU, Mesa's llvmpipe (software Vulkan, on the "
     "processor) is taken: usually slower than CPU, and said so", 1),
    ('auto', "Auto", "A discrete GPU where there is one, else the processor (never software Vulkan)", 2),
]


class WavecamCameraSettings(bpy.types.PropertyGroup):
    enabled: bpy.props.BoolProperty(
        name="wavecam", default=False, update=_turn_on_depth_output,
        description="Diffract every rendered frame through this pinhole (turns on the Z pass and OpenEXR output)")
    auto_film_distance: bpy.props.BoolProperty(
        name="Film at the lens", default=True,
        description="Film distance = the camera's focal length")
    film_distance: bpy.props.FloatProperty(
        name="Film distance", default=50.0, soft_min=1.0, soft_max=500.0, precision=2,
        unit='CAMERA', subtype='DISTANCE_CAMERA',
        description="Pinhole to film (mm), 0.1 mm or more")
    auto_pinhole: bpy.props.BoolProperty(
        name="Optimal pinhole", default=True,
        description="Rayleigh's optimum 1.9 sqrt(f lambda) at 550 nm for the film distance")
    pinhole: bpy.props.FloatProperty(
        name="Pinhole", default=0.3, soft_min=0.002, soft_max=5.0, precision=4, step=1,
        unit='CAMERA', subtype='DISTANCE_CAMERA',
        description="Pinhole diameter (mm): from the longest wavelength (0.0007 mm at 700 nm; a few wavelengths "
                    "to be useful) up to the film's width")
    wavelength_count: bpy.props.IntProperty(
        name="Wavelengths", default=8, soft_min=1, soft_max=64,
        description="Wavelengths sampled evenly over 400-700 nm; fewer than 3 give a grey (monochrome) image")
    use_wavelength_list: bpy.props.BoolProperty(
        name="List of wavelengths", default=False,
        description="Diffract at the listed wavelengths instead of a count over 400-700 nm")
    wavelength_list: bpy.props.StringProperty(
        name="Wavelength list", default="450nm,550nm,650nm",
        description="Increasing wavelengths from 100nm to 10um, e.g. 450nm,550nm,650nm")
    method: bpy.props.EnumProperty(
        name="Method", default='convolution', items=METHODS,
        description="How the diffracted image is formed: Convolution in seconds; Random phase and Incoherent "
                    "through the point sums, minutes to hours")
    auto_runs: bpy.props.BoolProperty(
        name="Runs from the PSF", default=True,
        description="As many random-phase runs as the PSF's size in pixels needs for every colour channel's "
                    "noise within 2% (64 to 1024; the job line says how many)")
    runs: bpy.props.IntProperty(
        name="Runs", default=64, soft_min=1, soft_max=1024,
        description="Random-phase runs averaged; noise falls as 1/sqrt(runs) once the PSF spans more pixels than runs")
    summation: bpy.props.EnumProperty(
        name="Summation", default='auto', items=SUMMATIONS,
        description="How the random-phase and incoherent methods evaluate their sums")
    device: bpy.props.EnumProperty(
        name="Device", default='cpu', items=DEVICES,
        description="Where the point sums' direct terms and the kernel summation's runs run")
    max_terms: bpy.props.FloatProperty(
        name="Max terms", default=DEFAULT_MAX_TERMS, min=1.0, soft_min=1e9, soft_max=1e14,
        description="Random-phase and incoherent: refuse a frame whose sums need more terms")
    max_terms_text: bpy.props.StringProperty(
        name="Max terms", get=_max_terms_text, set=_set_max_terms_text,
        description="Random-phase and incoherent: refuse a frame whose sums need more terms, a count such as 4e12 "
                    "(about an hour at 1e9 terms/s); beyond one machine, `wavecam farm` shares a job out on a "
                    "cluster")
    vignetting: bpy.props.BoolProperty(
        name="Vignetting", default=True,
        description="Keep the pinhole's natural cos^4 fall-off toward the corners (physical); off divides it out, "
                    "matching Blender's own brightness")

    def film_distance_mm(self, camera):
        return camera.lens if self.auto_film_distance else self.film_distance

    def pinhole_mm(self, camera):
        if self.auto_pinhole:
            return pinhole_design.optimal_diameter_mm(self.film_distance_mm(camera))
        return self.pinhole

    def wavelengths_text(self):
        """What the command's --wavelengths gets: the count, or the list without spaces."""
        return self.wavelength_list.replace(" ", "") if self.use_wavelength_list else str(self.wavelength_count)


def register():
    bpy.utils.register_class(WavecamCameraSettings)
    bpy.types.Camera.wavecam = bpy.props.PointerProperty(type=WavecamCameraSettings)


def unregister():
    del bpy.types.Camera.wavecam
    bpy.utils.unregister_class(WavecamCameraSettings)
