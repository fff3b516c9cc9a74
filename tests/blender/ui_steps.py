# The add-on with Blender's UI (run under xvfb-run by blender_addon_test.sh ui), where render
# handlers run on the render job's thread:
#   1. F12: a still, no file written; the diffracted frame must be saved, made, reported and
#      shown in an Image Editor by the add-on's main-thread timer, its fov the camera's.
#   2. Ctrl+F12: the two-frame animation (lens 35 -> 60 mm) writes both diffracted frames,
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


def render(animation):
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.render.render('INVOKE_DEFAULT', animation=animation)


def tick():
    scene = bpy.context.scene
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
        render(animation=False)
    elif state["phase"] == 1 and shown_wavecam_image():
        check_fov(shown_wavecam_image(), 35, "F12 still shown in an Image Editor")
        state["phase"] = 2
        render(animation=True)
    elif state["phase"] == 2:
        last = scene.render.frame_path(frame=2)[:-4] + ".wavecam.exr"
        if shown_wavecam_image() == last:
            check_fov(scene.render.frame_path(frame=1)[:-4] + ".wavecam.exr", 35, "Ctrl+F12 frame 1")
            check_fov(last, 60, "Ctrl+F12 frame 2 shown in an Image Editor")
            finish(0, "ui: passed")
    if time.time() - start > 150:
        finish(1, f"FAIL: phase {state['phase']}: no diffracted frame shown in an Image Editor within 150 s")
    return 0.5


bpy.app.timers.register(tick, first_interval=3.0)
