# Running `wavecam apply` on one frame, with the camera's settings as its flags.
import subprocess

from .preferences import wavecam_command


class WavecamRunError(Exception):
    pass


def apply_command(exe, camera, frame_path, out_path, fov_in_file):
    cmd = [exe, "apply", frame_path, "-o", out_path, "--film-distance", f"{camera.film_distance_mm:.9g}mm",
           "--wavelengths", camera.wavelengths, "--method", camera.method,
           "--depth-scale", f"{camera.depth_scale_m:.9g}m"]
    if camera.pinhole_mm is not None:
        cmd += ["--pinhole", f"{camera.pinhole_mm:.9g}mm"]
    if camera.method == 'random-phase':
        cmd += ["--runs", str(camera.runs)]
    if camera.method != 'convolution':
        cmd += ["--summation", camera.summation, "--device", camera.device]
    if not camera.vignetting:
        cmd += ["--no-vignetting"]
    if not fov_in_file:
        cmd += ["--fov", f"{camera.fov:.9g}deg"]
    return cmd


def run_wavecam(camera, frame_path, out_path, fov_in_file):
    """Diffracts frame_path into out_path; raises WavecamRunError with wavecam's own message."""
    exe = wavecam_command()
    if not exe:
        raise WavecamRunError("the wavecam command was not found: install wavecam, or set its path in "
                              "Preferences > Add-ons > wavecam")
    run = subprocess.run(apply_command(exe, camera, frame_path, out_path, fov_in_file),
                         capture_output=True, text=True)
    if run.returncode != 0:
        lines = [line for line in (run.stderr + run.stdout).splitlines() if line.strip()]
        raise WavecamRunError(lines[-1] if lines else f"wavecam exited with status {run.returncode}")
