# .blend files saved by earlier versions of the add-on. The method enum needs nothing (a file
# stores its number, and 0/1 kept their meaning: 'fast' is now convolution, 'exact'
# random-phase); the wavelengths, once one text field ("8" or "450nm,550nm,650nm"), are moved
# into the count or the list when the file is loaded.
import bpy
from bpy.app.handlers import persistent


def upgrade_camera(camera):
    w = camera.wavecam
    old = w.get("wavelengths")
    if camera.library is not None or not isinstance(old, str):
        return
    text = old.replace(" ", "")
    if text.isdigit() and 1 <= int(text) <= 1000:
        w.wavelength_count = int(text)
        w.use_wavelength_list = False
    else:  # a list, or text the render check will refuse by name
        w.wavelength_list = text
        w.use_wavelength_list = True
    del w["wavelengths"]


@persistent
def on_load_post(*args):
    for camera in bpy.data.cameras:
        upgrade_camera(camera)


def register():
    bpy.app.handlers.load_post.append(on_load_post)


def unregister():
    if on_load_post in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(on_load_post)
