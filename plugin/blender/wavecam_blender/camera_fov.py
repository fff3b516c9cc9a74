# The horizontal field of view of a camera as Blender renders it: the frame's corners from
# Camera.view_frame (which applies the sensor fit, the frame's aspect and portrait frames),
# hfov = 2 atan(max |x| / |z|). wavecam models a centred frame of square pixels seen through
# a perspective camera, so anything else is refused with the reason.
import math


class FovError(Exception):
    pass


def horizontal_fov_degrees(scene, camera_object):
    cam = camera_object.data
    render = scene.render
    if cam.type != 'PERSP':
        kind = cam.bl_rna.properties['type'].enum_items[cam.type].name
        raise FovError(f"camera '{camera_object.name}' is {kind}; wavecam needs a Perspective camera "
                       "(Camera > Lens > Type)")
    if cam.shift_x != 0 or cam.shift_y != 0:
        raise FovError(f"camera '{camera_object.name}' has shift ({cam.shift_x:g}, {cam.shift_y:g}); wavecam "
                       "assumes the frame is centred on the view axis: set Lens > Shift X and Y to 0")
    if render.pixel_aspect_x != render.pixel_aspect_y:
        raise FovError("pixel aspect is not 1 (Output > Format > Aspect); wavecam assumes square pixels")
    if render.use_border and render.use_crop_to_border:
        raise FovError("the frame is cropped to the render region (Output > Format > Crop to Render Region); "
                       "wavecam needs the whole frame")
    corners = cam.view_frame(scene=scene)
    half_width = max(abs(c.x) for c in corners)
    depth = abs(corners[0].z)
    return math.degrees(2 * math.atan(half_width / depth))
