# Running `wavecam apply` on one frame, with the camera's settings as its flags. The command
# prints its estimate, its progress and any refusal on stderr; a WavecamProcess reads those
# lines on a thread of its own, so that whoever waits for it (Blender's main thread with a UI,
# or the render itself in background mode) only looks at what has arrived.
import os
import queue
import shutil
import signal
import subprocess
import threading
import time

from . import command_output
from .preferences import wavecam_command


class WavecamRunError(Exception):
    pass


def setting_flags(camera, fov_in_file, max_terms=True):
    """The camera's settings as the command's flags; max_terms: with the panel's Max terms."""
    flags = ["--film-distance", f"{camera.film_distance_mm:.9g}mm", "--wavelengths", camera.wavelengths,
             "--method", camera.method, "--depth-scale", f"{camera.depth_scale_m:.9g}m"]
    if camera.pinhole_mm is not None:
        flags += ["--pinhole", f"{camera.pinhole_mm:.9g}mm"]
    if camera.method == 'random-phase' and camera.runs is not None:
        flags += ["--runs", str(camera.runs)]
    if camera.method != 'convolution':
        flags += ["--summation", camera.summation, "--device", camera.device]
        if max_terms:
            flags += ["--max-terms", f"{camera.max_terms:.6g}"]
    if not camera.vignetting:
        flags += ["--no-vignetting"]
    if not fov_in_file:
        flags += ["--fov", f"{camera.fov:.9g}deg"]
    return flags


def apply_command(exe, camera, frame_path, out_path, fov_in_file, verb=("apply",)):
    """The command line; verb ("farm", "submit") gives the same job for a cluster, each share
    within the command's default limit."""
    return [exe, *verb, frame_path, "-o", out_path, *setting_flags(camera, fov_in_file, verb == ("apply",))]


class WavecamProcess:
    """`wavecam apply` started; lines() gives what it printed since the last call."""

    def __init__(self, camera, frame_path, out_path, fov_in_file, nice=0):
        """nice: how much lower than Blender's the command's CPU priority is (with a window,
        the UI is drawn on the same cores)."""
        exe = wavecam_command()
        if not exe:
            raise WavecamRunError("the wavecam command was not found: install wavecam, or set its path in "
                                  "Preferences > Add-ons > wavecam")
        self.command = apply_command(exe, camera, frame_path, out_path, fov_in_file)
        self.farm_command = apply_command(exe, camera, frame_path, out_path, fov_in_file, verb=("farm", "submit"))
        self.max_terms = camera.max_terms
        self.printed = []
        self._lines = queue.Queue()
        niced = ["nice", "-n", str(nice)] if nice and shutil.which("nice") else []  # nice execs: the same pid
        self._process = subprocess.Popen(niced + self.command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                         stdin=subprocess.DEVNULL, text=True, bufsize=1)
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    @property
    def pid(self):
        return self._process.pid

    def _read(self):
        for line in self._process.stdout:
            self._lines.put(line.rstrip("\n"))
        self._process.stdout.close()

    def lines(self):
        new = []
        while not self._lines.empty():
            new.append(self._lines.get())
        self.printed += new
        return new

    def finished(self):
        """True once the command has ended and every line it printed has been read."""
        return self._process.poll() is not None and not self._reader.is_alive()

    def wait(self):
        self._process.wait()
        self._reader.join()

    def interrupt(self):
        """Asks the command to stop, as Ctrl+C does: it removes the file it was writing and
        ends within about 1.5 s (its own watchdog)."""
        if self._process.poll() is None:
            self._process.send_signal(signal.SIGINT)

    def kill(self):
        if self._process.poll() is None:
            self._process.kill()

    def error(self):
        """None when the frame was written, else the command's own message (as the panel says it)."""
        self.lines()
        if self._process.returncode == 0:
            return None
        lines = [line for line in self.printed if line.strip()]
        if not lines:
            return f"wavecam exited with status {self._process.returncode}"
        return command_output.refusal_text(lines[-1], self.farm_command, self.max_terms)


def run_wavecam(camera, frame_path, out_path, fov_in_file, on_line=None):
    """Diffracts frame_path into out_path and waits (background mode); each line the command
    prints goes to on_line as it comes. Raises WavecamRunError with wavecam's own message."""
    process = WavecamProcess(camera, frame_path, out_path, fov_in_file)
    while True:
        done = process.finished()
        for line in process.lines():
            if on_line:
                on_line(line)
        if done:
            break
        time.sleep(0.1)
    error = process.error()
    if error:
        raise WavecamRunError(error)
    if not os.path.isfile(out_path):
        raise WavecamRunError(f"{out_path}: wavecam wrote nothing")
