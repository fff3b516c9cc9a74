# Esc ends a running diffraction as it ends a render: a modal operator in every window lets
# every other event through and, on Esc, cancels the diffraction (diffraction_queue.cancel).
# It ends itself at the first event after the diffraction is over. While Blender's render job
# still runs, Esc goes on to it and cancels it too.
import bpy

_watched = set()  # windows (as_pointer) with a watcher running


class WAVECAM_OT_watch_escape(bpy.types.Operator):
    """Cancels wavecam's diffraction on Esc"""
    bl_idname = "wavecam.watch_escape"
    bl_label = "wavecam: Esc cancels"
    bl_options = {'INTERNAL'}

    def invoke(self, context, event):
        self._window = context.window.as_pointer()
        _watched.add(self._window)
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        from . import diffraction_queue
        if not diffraction_queue.busy():
            _watched.discard(self._window)
            return {'FINISHED', 'PASS_THROUGH'}
        if event.type == 'ESC' and event.value == 'PRESS':
            diffraction_queue.cancel("Esc")
            if not bpy.app.is_job_running('RENDER'):
                return {'RUNNING_MODAL'}  # taken, as a render's Esc is (the render window stays)
        return {'PASS_THROUGH'}


class WAVECAM_OT_cancel(bpy.types.Operator):
    """Stop wavecam's diffraction now: the frame being diffracted and those waiting are left as Blender rendered them"""
    bl_idname = "wavecam.cancel"
    bl_label = "Cancel diffraction"

    def execute(self, context):
        from . import diffraction_queue
        diffraction_queue.cancel("cancelled")
        return {'FINISHED'}


def watch_every_window():
    """Starts a watcher in each window that has none; where Blender refuses an operator at this
    moment (while it draws or finishes a render), that window is tried again at the next call."""
    for window in bpy.context.window_manager.windows:
        if window.as_pointer() not in _watched:
            try:
                with bpy.context.temp_override(window=window, screen=window.screen):
                    bpy.ops.wavecam.watch_escape('INVOKE_DEFAULT')
            except RuntimeError:
                pass


def register():
    bpy.utils.register_class(WAVECAM_OT_watch_escape)
    bpy.utils.register_class(WAVECAM_OT_cancel)


def unregister():
    bpy.utils.unregister_class(WAVECAM_OT_cancel)
    bpy.utils.unregister_class(WAVECAM_OT_watch_escape)
    _watched.clear()
