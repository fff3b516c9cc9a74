# Diffraction with Blender's window open: frames wait here and `wavecam apply` runs as a
# subprocess, one frame at a time, looked at by a main-thread timer ten times a second. Blender
# stays responsive; the command's estimate goes to the Info log, its progress to a bar in the
# status bar and the panel (progress_display.py); Esc (escape_watch.py) or the panel's Cancel ends the command,
# which removes the file it was writing and leaves an earlier result as it was, and the frames
# still waiting are dropped.
# In background mode (blender -b) there is no event loop: frames are diffracted in the render
# handler itself (frame_handler.py).
import atexit
import os
import queue
import time

import bpy

from . import command_output, escape_watch, progress_display, reports
from .wavecam_run import WavecamProcess, WavecamRunError


COMMAND_NICENESS = 10  # the command yields the cores to Blender's drawing and rendering


class Job:
    def __init__(self, scene_name, frame, frame_path, out_path, camera, fov_in_file):
        self.scene_name, self.frame = scene_name, frame
        self.frame_path, self.out_path = frame_path, out_path
        self.camera, self.fov_in_file = camera, fov_in_file
        self.started = None
        self.estimate = None
        self.progress = None  # (percent, 'about 40s left')


_waiting = queue.Queue()  # filled by the render thread's handlers, emptied by the timer
_running = {"job": None, "process": None}
_dropping = {"render": False}  # cancelled while Blender's render still runs: its later frames are dropped


def submit(job):
    """Called from any thread: the frame is diffracted after those before it."""
    if _dropping["render"]:
        reports.info(f"frame {job.frame}: not diffracted (cancelled)")
        return
    _waiting.put(job)


def render_started():
    _dropping["render"] = False


def busy():
    return _running["process"] is not None or not _waiting.empty()


def running_pid():
    """The process id of the command now running, or None (for tests)."""
    return _running["process"].pid if _running["process"] else None


def bar_status():
    """(percent, what the progress bar says): the running frame, and its time left once known."""
    job = _running["job"]
    if job is None:
        return 0.0, "wavecam"
    left = job.progress[1] if job.progress else "starting"
    return (float(job.progress[0]) if job.progress else 0.0), f"wavecam: frame {job.frame}, {left}"


def status_text():
    """What the status bar says now, or None when nothing runs."""
    job = _running["job"]
    if job is None:
        return None
    more = _waiting.qsize()
    waiting = f" ({more} more frame{'s' if more > 1 else ''} waiting)" if more else ""
    if job.progress:
        done = f"{job.progress[0]}% after {time.monotonic() - job.started:.0f}s, {job.progress[1]}"
    else:
        done = f"diffracting, {time.monotonic() - job.started:.0f}s" + (f" of {job.estimate}" if job.estimate else "")
    return f"wavecam: frame {job.frame}: {done}{waiting}. Esc cancels"


def cancel(why="cancelled"):
    """Ends the running command and drops the frames waiting; no file is left for them. The
    command is asked to stop and looked after by the timer (killed if it lingers), so that
    Blender does not wait for it."""
    job, process = _running["job"], _running["process"]
    dropped = []
    while not _waiting.empty():
        dropped.append(_waiting.get().frame)
    kept = None  # an earlier render's result: the command leaves it as it was, and so does the add-on
    if process is not None:
        process.interrupt()
        _stopping.append((process, time.monotonic()))
        kept = job.out_path if os.path.isfile(job.out_path) else None
        dropped.insert(0, job.frame)
    _running["job"] = _running["process"] = None
    _dropping["render"] = bpy.app.is_job_running('RENDER')
    progress_display.clear()
    if dropped:
        names = ", ".join(str(f) for f in dropped)
        earlier = f" (the earlier {os.path.basename(kept)} kept)" if kept else ""
        reports.info(f"{why}: frame{'s' if len(dropped) > 1 else ''} {names} not diffracted; no file written{earlier}")


_stopping = []  # (process, when it was asked to stop)
STOP_GRACE_S = 3.0


def _look_after_stopping():
    for item in list(_stopping):
        process, asked = item
        if process.finished():
            _stopping.remove(item)
        elif time.monotonic() - asked > STOP_GRACE_S:
            process.kill()


def stopping_pids():
    """Commands cancelled and not yet ended (for tests)."""
    return [process.pid for process, _ in _stopping]


def _start(job):
    job.started = time.monotonic()
    try:
        _running["process"] = WavecamProcess(job.camera, job.frame_path, job.out_path, job.fov_in_file,
                                             nice=COMMAND_NICENESS)
        _running["job"] = job
    except (WavecamRunError, OSError) as e:
        reports.error(f"frame {job.frame}: {e}")


def _read(job, line):
    if command_output.device_warning(line):
        reports.warning(f"frame {job.frame}: {command_output.device_warning(line)}")
    if command_output.estimate(line):
        job.estimate = command_output.estimate(line)
        reports.info(f"frame {job.frame}: {line.removeprefix('apply: ')}; Esc cancels")
    elif command_output.progress(line):
        job.progress = command_output.progress(line)


def _finish(job, process):
    _running["job"] = _running["process"] = None
    error = process.error()
    if error:
        reports.error(f"frame {job.frame}: {error}")
    else:
        reports.info(f"frame {job.frame}: wrote {job.out_path}")
        reports.show_image(job.out_path)


def _poll():
    try:
        _look_after_stopping()
        job, process = _running["job"], _running["process"]
        if process is None and not _waiting.empty():
            _start(_waiting.get())
        elif process is not None:
            escape_watch.watch_every_window()  # (each window once; again where Blender refused)
            done = process.finished()
            for line in process.lines():
                _read(job, line)
            if done:
                _finish(job, process)
        text = status_text()
        if text:
            progress_display.show(text, *bar_status())
        else:
            progress_display.clear()
    except Exception as e:  # the timer must go on
        reports.error(f"unexpected failure: {type(e).__name__}: {e}")
    return 0.1 if busy() or _stopping else 0.25


def _on_exit():
    """Blender quitting: the command is not left running on its own."""
    for process in [_running["process"]] + [p for p, _ in _stopping]:
        if process is not None:
            process.kill()


def register():
    if not bpy.app.background:
        bpy.app.timers.register(_poll, first_interval=0.25, persistent=True)
        atexit.register(_on_exit)


def unregister():
    if bpy.app.timers.is_registered(_poll):
        bpy.app.timers.unregister(_poll)
    atexit.unregister(_on_exit)
    if _running["process"] is not None:
        cancel("wavecam turned off")
    for process, _ in _stopping:
        process.kill()
    progress_display.clear()
