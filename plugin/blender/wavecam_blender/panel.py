# Properties > Camera data > wavecam Pinhole. Every message is drawn as wrapped rows
# (wrapped_label.py); what the render would refuse is shown while it stands, else the job's
# estimate (job_estimate.py), and a running diffraction's progress bar with its cancel cross.
import bpy

from . import camera_fov, diffraction_queue, job_estimate, progress_display, settings_check, wrapped_label


def problem(scene, camera_object):
    """What the render would refuse for this camera now, or None."""
    try:
        fov = camera_fov.horizontal_fov_degrees(scene, camera_object)
        settings_check.check_settings(camera_object.data, fov)
        settings_check.check_output(scene)
        settings_check.check_command()
    except (camera_fov.FovError, settings_check.SettingError) as e:
        return str(e)
    return None


def _menu(layout, settings, prop):
    """An enum's name above its menu: beside it, a narrow panel cuts the name."""
    column = layout.column(align=True)
    column.label(text=settings.bl_rna.properties[prop].name)
    column.prop(settings, prop, text="")


class DATA_PT_wavecam(bpy.types.Panel):
    bl_label = "wavecam Pinhole"
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
        status = diffraction_queue.status_text()
        if status:  # the bar and its cancel cross first: they stay put as the text below rewraps
            progress_display.draw_bar(layout, context)
            wrapped_label.draw(layout, context, status.removeprefix("wavecam: "), icon='RENDER_RESULT', box=True)
        layout.active = w.enabled
        layout.prop(w, "auto_film_distance")
        if w.auto_film_distance:
            wrapped_label.draw(layout, context, f"Film distance {cam.lens:.1f} mm (the lens)")
        else:
            layout.prop(w, "film_distance")
        layout.prop(w, "auto_pinhole")
        if w.auto_pinhole:
            wrapped_label.draw(layout, context, f"Pinhole {w.pinhole_mm(cam):.3f} mm: Rayleigh's optimum "
                                                "1.9 sqrt(f lambda) at 550 nm")
        else:
            layout.prop(w, "pinhole")
        layout.prop(w, "use_wavelength_list")
        layout.prop(w, "wavelength_list" if w.use_wavelength_list else "wavelength_count")
        _menu(layout, w, "method")
        if w.method == 'random-phase':
            layout.prop(w, "auto_runs")
            if not w.auto_runs:
                layout.prop(w, "runs")
        if w.method != 'convolution':
            _menu(layout, w, "summation")
            _menu(layout, w, "device")
            layout.prop(w, "max_terms_text")
        layout.prop(w, "vignetting")
        scale = context.scene.unit_settings.scale_length
        wrapped_label.draw(layout, context, f"Depth: 1 Blender unit = {scale:g} m (Scene > Units > Unit Scale)")
        camera_object = context.object if context.object and context.object.data == cam else None
        refusal = problem(context.scene, camera_object) if camera_object and w.enabled else None
        if refusal:
            wrapped_label.draw(layout, context, f"Not diffracted: {refusal}", icon='ERROR', box=True)
        elif camera_object and w.enabled and not status:  # (none while a frame diffracts: it has its own)
            estimate = job_estimate.panel_text(context, camera_object)
            if estimate:
                wrapped_label.draw(layout, context, estimate, icon='TIME')


def register():
    bpy.utils.register_class(DATA_PT_wavecam)


def unregister():
    bpy.utils.unregister_class(DATA_PT_wavecam)
