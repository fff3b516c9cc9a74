# Properties > Camera data > wavecam.
import bpy

from . import camera_fov, settings_check


def _problem(scene, camera_object):
    """What settings_check would refuse for this camera now, or None."""
    try:
        fov = camera_fov.horizontal_fov_degrees(scene, camera_object)
        settings_check.check_settings(camera_object.data, fov)
    except (camera_fov.FovError, settings_check.SettingError) as e:
        return str(e)
    return None


class DATA_PT_wavecam(bpy.types.Panel):
    bl_label = "wavecam pinhole"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.camera is not None

    def draw_header(self, context):
        self.layout.prop(context.camera.wavecam, "enabled", text="")

    def draw(self, context):
        cam = context.camera
        w = cam.wavecam
        layout = self.layout
        layout.use_property_split = True
        layout.active = w.enabled
        layout.prop(w, "auto_film_distance")
        row = layout.row()
        if w.auto_film_distance:
            row.label(text=f"Film distance {cam.lens:.1f} mm (the lens)")
        else:
            row.prop(w, "film_distance")
        layout.prop(w, "auto_pinhole")
        if w.auto_pinhole:
            layout.label(text=f"Pinhole {w.pinhole_mm(cam):.3f} mm (1.9 sqrt(f lambda), 550 nm)")
        else:
            layout.prop(w, "pinhole")
        layout.prop(w, "use_wavelength_list")
        layout.prop(w, "wavelength_list" if w.use_wavelength_list else "wavelength_count")
        layout.prop(w, "method")
        if w.method == 'random-phase':
            layout.prop(w, "runs")
        if w.method != 'convolution':
            layout.prop(w, "summation")
            layout.prop(w, "device")
        layout.prop(w, "vignetting")
        scale = context.scene.unit_settings.scale_length
        layout.label(text=f"Depth: 1 Blender unit = {scale:g} m (Scene > Units > Unit Scale)")
        camera_object = context.object if context.object and context.object.data == cam else None
        problem = _problem(context.scene, camera_object) if camera_object and w.enabled else None
        if problem:
            layout.label(text=problem, icon='ERROR')


def register():
    bpy.utils.register_class(DATA_PT_wavecam)


def unregister():
    bpy.utils.unregister_class(DATA_PT_wavecam)
