# The add-on with Blender's UI (run under xvfb-run by blender_addon_test.sh ui), where render
# handlers run on the render job's thread:
#   1. F12: a still, no file written; the diffracted frame must be saved, made, reported and
#      shown in an Image Editor by the add-on's main-thread timer, its fov the camera's.
#      Its report ("wrote ...") must be in the Info editor's log, read back through the clipboard.
#   2. F12 with the camera shifted: refused when the render starts, the error in the Info log.
#   3. Ctrl+F12: the two-frame animation (lens 35 -> 60 mm) writes both diffracted frames,
#      each with its own frame's fov, and the last is shown.
import math
import os
import time

import bpy
import OpenImageIO as oiio

start = time.time()
state = {"phase": 0}


def finish(code, message):
    print(message, flush=True)
    os._exit(code)  # quit now, from inside a timer, with the status


def shown_wavecam_image():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            image = area.spaces.active.image if area.type == 'IMAGE_EDITOR' else None
            if image is not None and image.filepath.endswith(".wavecam.exr"):
                return bpy.path.abspath(image.filepath)
    return None


def fov_of(path):
    source = oiio.ImageInput.open(path)
    return source.spec().getattribute("wavecam.fov") if source else None


def true_fov(lens):  # the scene's landscape frame, sensor fit Auto
    return math.degrees(2 * math.atan(bpy.context.scene.camera.data.sensor_width / 2 / lens))


def check_fov(path, lens, what):
    fov, truth = fov_of(path), true_fov(lens)
    if fov is None or abs(fov - truth) >= 0.01:
        finish(1, f"FAIL: {what}: {path} wavecam.fov {fov}, camera {truth:.4f}")
    print(f"{what}: {path}, wavecam.fov {fov:.4f} (camera {truth:.4f})", flush=True)


def info_log():
    """Every line of the Info editor's log (the reports the status bar showed), via the clipboard."""
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'INFO')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
        bpy.ops.info.select_all(action='SELECT')
        bpy.ops.info.report_copy()
    return bpy.context.window_manager.clipboard.splitlines()


def logged(text):
    return [line for line in info_log() if text in line]


def render(animation):
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.render.render('INVOKE_DEFAULT', animation=animation)


def tick():
    scene = bpy.context.scene
    if bpy.app.is_job_running('RENDER') and time.time() - start <= 150:
        # nothing touched while a render job runs or winds down (a refused render's job still
        # cancelling when the Info log was read and the next render started crashed Blender
        # under load)
        return 0.5
    if state["phase"] == 0:
        state["phase"] = 1
        window = bpy.context.window_manager.windows[0]
        # the camera's data tab in the Properties editor, so the wavecam panel draws (a failing
        # draw prints a Python traceback, which the test looks for)
        bpy.context.view_layer.objects.active = scene.camera
        for area in window.screen.areas:
            if area.type == 'PROPERTIES':
                area.spaces.active.context = 'DATA'
                area.tag_redraw()
        # the timeline becomes an Info editor, whose log the test reads
        next(a for a in window.screen.areas if a.type == 'DOPESHEET_EDITOR').type = 'INFO'
        render(animation=False)
    elif state["phase"] == 1 and shown_wavecam_image():
        if "wrote" not in state:
            check_fov(shown_wavecam_image(), 35, "F12 still shown in an Image Editor")
            state["wrote"] = time.time()
        if not logged("wavecam: frame 1: wrote "):
            if time.time() - state["wrote"] > 10:
                finish(1, f"FAIL: no 'wavecam: frame 1: wrote' in the Info log: {info_log()}")
            return 0.5
        print(f"Info log: {logged('wavecam: frame 1: wrote ')[0]}", flush=True)
        scene.camera.data.shift_x = 0.1
        state["phase"] = 2
        render(animation=False)
    elif state["phase"] == 2 and logged("has shift"):
        print(f"Info log: {logged('has shift')[0]}", flush=True)
        scene.camera.data.shift_x = 0
        state["phase"] = 3
        render(animation=True)
    elif state["phase"] == 3:
        last = scene.render.frame_path(frame=2)[:-4] + ".wavecam.exr"
        if shown_wavecam_image() == last:
            check_fov(scene.render.frame_path(frame=1)[:-4] + ".wavecam.exr", 35, "Ctrl+F12 frame 1")
            check_fov(last, 60, "Ctrl+F12 frame 2 shown in an Image Editor")
            finish(0, "ui: passed")
    if time.time() - start > 150:
        finish(1, f"FAIL: phase {state['phase']} not done within 150 s (1: the still shown, 2: the refusal in "
                  f"the Info log, 3: the animation shown); Info log: {info_log()}")
    return 0.5


bpy.app.timers.register(tick, first_interval=3.0)
