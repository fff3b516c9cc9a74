# The add-on with Blender's UI (run under xvfb-run by blender_addon_test.sh ui): F12 renders a
# still in the render job's thread and writes no file; the diffracted frame must be saved,
# made, reported and shown in an Image Editor by the add-on's main-thread timer.
import math
import os
import sys
import time

import bpy

start = time.time()
state = {"rendering": False}


def finish(code, message):
    print(message, flush=True)
    os._exit(code)  # quit now, from inside a timer, with the status


def shown_wavecam_image():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            image = area.spaces.active.image if area.type == 'IMAGE_EDITOR' else None
            if image is not None and image.filepath.endswith(".wavecam.exr"):
                return image
    return None


def tick():
    if not state["rendering"]:
        state["rendering"] = True
        window = bpy.context.window_manager.windows[0]
        # the camera's data tab in the Properties editor, so the wavecam panel draws (a failing
        # draw prints a Python traceback, which the test looks for)
        camera = bpy.context.scene.camera
        bpy.context.view_layer.objects.active = camera
        for area in window.screen.areas:
            if area.type == 'PROPERTIES':
                area.spaces.active.context = 'DATA'
                area.tag_redraw()
        with bpy.context.temp_override(window=window, screen=window.screen):
            bpy.ops.render.render('INVOKE_DEFAULT')  # F12
        return 1.0
    image = shown_wavecam_image()
    if image is not None:
        import OpenImageIO as oiio
        path = bpy.path.abspath(image.filepath)
        source = oiio.ImageInput.open(path)
        fov = source.spec().getattribute("wavecam.fov") if source else None
        cam = bpy.context.scene.camera.data  # the scene's landscape frame, sensor fit Auto
        truth = math.degrees(2 * math.atan(cam.sensor_width / 2 / cam.lens))
        ok = fov is not None and abs(fov - truth) < 0.01
        finish(0 if ok else 1, f"{'' if ok else 'FAIL: '}shown in an Image Editor: {path}, wavecam.fov {fov} "
                               f"(camera {truth:.4f})")
    if time.time() - start > 90:
        finish(1, "FAIL: no diffracted frame shown in an Image Editor within 90 s")
    return 0.5


bpy.app.timers.register(tick, first_interval=3.0)
