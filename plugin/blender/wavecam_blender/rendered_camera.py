# What a frame needs from its camera, copied out of Blender's data: the render depsgraph's
# evaluated camera (an animated lens is evaluated there, not on the scene that render_write
# receives; checked: with -a, frame 2 saw frame 1's lens there) does not outlive the frame.
from . import camera_fov, settings_check


class RenderedCamera:
    def __init__(self, scene, camera_object):
        cam, w = camera_object.data, camera_object.data.wavecam
        try:
            self.fov, self.fov_error = camera_fov.horizontal_fov_degrees(scene, camera_object), None
        except camera_fov.FovError as e:
            self.fov, self.fov_error = None, str(e)
        self.settings_error = None
        if self.fov is not None:
            try:
                settings_check.check_settings(cam, self.fov)
            except settings_check.SettingError as e:
                self.settings_error = str(e)
        self.film_distance_mm = w.film_distance_mm(cam)
        self.pinhole_mm = None if w.auto_pinhole else w.pinhole  # None: wavecam's optimum for the film
        self.wavelengths = w.wavelengths_text()
        self.method = w.method
        self.runs = None if w.auto_runs else w.runs  # None: wavecam's count from the PSF
        self.summation = w.summation
        self.device = w.device
        self.max_terms = w.max_terms
        self.vignetting = w.vignetting
        # Blender's Unit Scale: metres per Blender unit, the unit of the depth pass
        self.depth_scale_m = scene.unit_settings.scale_length
