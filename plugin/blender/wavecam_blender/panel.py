# Properties > Camera data > wavecam.
import bpy


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
        layout.prop(w, "wavelengths")
        layout.prop(w, "method")
        if w.method == 'exact':
            layout.prop(w, "runs")
        if cam.shift_x or cam.shift_y:
            layout.label(text="Shift must be 0: wavecam needs a centred frame", icon='ERROR')


def register():
    bpy.utils.register_class(DATA_PT_wavecam)


def unregister():
    bpy.utils.unregister_class(DATA_PT_wavecam)
