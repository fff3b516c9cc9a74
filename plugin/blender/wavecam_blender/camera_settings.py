# The wavecam settings a camera carries (camera.data.wavecam). The pinhole and film distance
# follow the camera's lens unless set by hand.
import bpy

from . import pinhole_design


def _turn_on_depth_output(settings, context):
    """Enabling wavecam makes Blender write what wavecam reads: an OpenEXR with a depth pass."""
    scene = context.scene if context else None
    if not settings.enabled or scene is None:
        return
    for layer in scene.view_layers:
        layer.use_pass_z = True
    image = scene.render.image_settings
    if image.file_format not in {'OPEN_EXR', 'OPEN_EXR_MULTILAYER'}:
        image.file_format = 'OPEN_EXR_MULTILAYER'
        image.color_depth = '32'
    if image.file_format == 'OPEN_EXR':
        image.use_zbuffer = True


class WavecamCameraSettings(bpy.types.PropertyGroup):
    enabled: bpy.props.BoolProperty(
        name="wavecam", default=False, update=_turn_on_depth_output,
        description="Diffract every rendered frame through this pinhole (turns on the Z pass and OpenEXR output)")
    auto_film_distance: bpy.props.BoolProperty(
        name="Film at the lens", default=True,
        description="Film distance = the camera's focal length")
    film_distance: bpy.props.FloatProperty(
        name="Film distance", default=50.0, min=0.1, soft_max=500.0, unit='CAMERA', subtype='DISTANCE_CAMERA',
        description="Pinhole to film (mm)")
    auto_pinhole: bpy.props.BoolProperty(
        name="Optimal pinhole", default=True,
        description="Rayleigh's optimum 1.9 sqrt(f lambda) at 550 nm for the film distance")
    pinhole: bpy.props.FloatProperty(
        name="Pinhole", default=0.3, min=0.001, soft_max=10.0, precision=3, unit='CAMERA',
        subtype='DISTANCE_CAMERA', description="Pinhole diameter (mm)")
    wavelengths: bpy.props.StringProperty(
        name="Wavelengths", default="8",
        description="A count over 400-700 nm (e.g. 8) or a list such as 450nm,550nm,650nm")
    method: bpy.props.EnumProperty(
        name="Method", default='fast',
        items=[('fast', "Fast", "PSF grid and FFT convolution"),
               ('exact', "Exact", "The seed paper's random-phase sum (slow; small frames)"),
               ('incoherent', "Incoherent", "The exact sum with every source alone (very slow)")])
    runs: bpy.props.IntProperty(
        name="Runs", default=8, min=1, max=100000,
        description="Exact method: random-phase runs averaged; noise falls as 1/sqrt(runs)")

    def film_distance_mm(self, camera):
        return camera.lens if self.auto_film_distance else self.film_distance

    def pinhole_mm(self, camera):
        if self.auto_pinhole:
            return pinhole_design.optimal_diameter_mm(self.film_distance_mm(camera))
        return self.pinhole


def register():
    bpy.utils.register_class(WavecamCameraSettings)
    bpy.types.Camera.wavecam = bpy.props.PointerProperty(type=WavecamCameraSettings)


def unregister():
    del bpy.types.Camera.wavecam
    bpy.utils.unregister_class(WavecamCameraSettings)
