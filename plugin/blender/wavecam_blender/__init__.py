# wavecam for Blender: after each rendered frame, the image a real pinhole camera makes.
#
# A panel on the camera (Properties > Camera data > wavecam Pinhole) sets the pinhole; when on,
# every frame Blender writes (F12 with a file, `blender -b scene.blend -f N` or `-a`) gets its
# exact horizontal field of view written into its EXR as `wavecam.fov`, and `wavecam apply`
# writes the diffracted frame beside it as NAME.wavecam.exr (with a window, off Blender's main
# thread, its progress shown and Esc cancelling it).
bl_info = {
    "name": "wavecam",
    "author": "wavecam developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Camera data > wavecam Pinhole",
    "description": "Diffract each rendered frame through a real pinhole with the wavecam command",
    "category": "Render",
}

from . import (camera_settings, diffraction_queue, escape_watch, frame_handler, old_files, panel, preferences,
               progress_display, reports)

_modules = (preferences, camera_settings, old_files, panel, reports, escape_watch, progress_display, diffraction_queue,
            frame_handler)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
