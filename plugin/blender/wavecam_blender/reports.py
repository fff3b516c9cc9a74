# Messages and results reach the user without touching Blender's data from the render thread:
# in background mode they are printed (stdout for information, stderr for errors); with a UI
# they are also queued, and a main-thread timer turns them into reports in the status bar and
# the Info editor, and shows the diffracted frame in an Image Editor.
#
# A report reaches the status bar and the Info editor only from an operator that the window
# manager runs: an operator called from Python (a timer) has its reports printed and dropped,
# and an ERROR report makes the call raise. So the timer invokes WAVECAM_OT_report in a
# window's context (the front one: an error's popup opens there, not behind the render
# window); it starts modal, and reports from its first timer event, run by the window
# manager's event loop.
import os
import queue
import sys

import bpy

_pending = queue.Queue()
_delays = {}  # id of a pending item -> drains it has waited for Blender


def info(message):
    _emit('INFO', message)


def warning(message):
    _emit('WARNING', message)


def error(message):
    _emit('ERROR', message)


def show_image(path):
    if not bpy.app.background:
        _pending.put(('show', path))


def on_main_thread(function, *args):
    """Runs `function` now in background mode, else soon from the main-thread timer (render
    handlers may run on the render thread, where Blender's data must not change)."""
    if bpy.app.background:
        function(*args)
    else:
        _pending.put(('call', function, args))


def _emit(level, message):
    stream = sys.stderr if level == 'ERROR' else sys.stdout
    prefix = {'ERROR': "error: ", 'WARNING': "warning: "}.get(level, "")
    print(f"wavecam: {prefix}{message}", file=stream, flush=True)
    if not bpy.app.background:
        _pending.put(('report', level, message))


class WAVECAM_OT_report(bpy.types.Operator):
    """Shows a wavecam message in the status bar and the Info editor"""
    bl_idname = "wavecam.report"
    bl_label = "wavecam report"
    bl_options = {'INTERNAL'}

    level: bpy.props.EnumProperty(items=[('INFO', "Info", ""), ('WARNING', "Warning", ""), ('ERROR', "Error", "")])
    message: bpy.props.StringProperty()

    def invoke(self, context, event):
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.0, window=context.window)
        wm.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        context.window_manager.event_timer_remove(self._timer)
        self.report({self.level}, f"wavecam: {self.message}")
        return {'FINISHED'}


def front_window():
    """The window the user looks at after a render: the render window (a temporary screen)
    where there is one, else the newest window. An error's popup opens there."""
    windows = list(bpy.context.window_manager.windows)
    return next((w for w in reversed(windows) if w.screen.is_temporary), windows[-1])


def _report(level, message):
    window = front_window()
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.wavecam.report('INVOKE_DEFAULT', level=level, message=message)


def _load(path):
    """One image datablock for wavecam's results, whatever the frame: an animation's frames
    replace each other in it rather than fill the .blend with one image each. Shown as Blender
    shows its Render Result: through the scene's view transform, look, exposure and gamma."""
    shown = [image for image in bpy.data.images if image.filepath.endswith(".wavecam.exr")]
    image = shown[0] if shown else bpy.data.images.load(path)
    if os.path.abspath(bpy.path.abspath(image.filepath)) != os.path.abspath(path):
        image.filepath = path
    image.reload()
    image.name = os.path.basename(path)
    image.use_view_as_render = True
    return image


def _show(path):
    image = _load(path)
    editors = [area.spaces.active for window in bpy.context.window_manager.windows
               for area in window.screen.areas if area.type == 'IMAGE_EDITOR']
    # an editor showing nothing or an earlier wavecam frame first, else the render view
    free = [s for s in editors if s.image is None or s.image.filepath.endswith(".wavecam.exr")]
    for space in free or [s for s in editors if s.image and s.image.type == 'RENDER_RESULT'][:1]:
        space.image = image
    if not editors:
        info(f"{os.path.basename(path)} loaded as image '{image.name}'; open it in an Image Editor")


def _rendering():
    """Blender is rendering: its data may not be written (an image's path, name or view)."""
    return bpy.app.is_job_running('RENDER')


def _not_now(e):
    """Blender refused to have its data written at this moment (while it draws or finishes a
    render, even from a timer): the same call goes through a moment later."""
    return "in this state" in str(e) or "not allowed" in str(e)


_MAX_DELAYS = 240  # drains (2 minutes) an item may wait for Blender before it is given up


def _drain():
    held = []  # items Blender could not take yet, in order: shown images while it renders
    while not _pending.empty():
        item = _pending.get()
        if item[0] == 'show' and _rendering():
            held.append(item)
            continue
        try:
            if item[0] == 'report':
                _report(item[1], item[2])
            elif item[0] == 'call':
                item[1](*item[2])
            else:
                _show(item[1])
            _delays.pop(id(item), None)
        except Exception as e:  # one failure must not stop later messages
            _delays[id(item)] = _delays.get(id(item), 0) + 1
            if _not_now(e) and _delays[id(item)] < _MAX_DELAYS:
                held.append(item)
            else:
                _delays.pop(id(item), None)
                print(f"wavecam: error: {item[0]} {item[1]}: {e}", file=sys.stderr)
    for item in held:
        _pending.put(item)
    return 0.5


def register():
    bpy.utils.register_class(WAVECAM_OT_report)
    if not bpy.app.background:
        bpy.app.timers.register(_drain, first_interval=0.5, persistent=True)


def unregister():
    if bpy.app.timers.is_registered(_drain):
        bpy.app.timers.unregister(_drain)
    bpy.utils.unregister_class(WAVECAM_OT_report)
