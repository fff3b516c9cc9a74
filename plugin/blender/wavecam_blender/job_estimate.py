# The panel's estimate before the render: `wavecam estimate` on a description of the frame the
# camera will render (its size in pixels, field of view and nearest depth), with the flags the
# render will pass. The command resolves and prices the job as `wavecam apply` does (the same
# chooser, the rate measured here as it starts), so the panel and the job's own line agree.
# The nearest depth is found by casting rays through a grid over the frame; the command runs
# on a thread of its own, once for each change of what the estimate depends on.
import math
import re
import subprocess
import threading

import bpy
from mathutils import Vector

from . import wavecam_run
from .preferences import wavecam_command
from .rendered_camera import RenderedCamera

RAYS_ACROSS = 32  # the grid's columns; its rows follow the frame's aspect
_ESTIMATE = re.compile(r"^estimate: (?P<job>.*) = (?P<terms>[0-9.e+-]+) terms, about (?P<time>\S+) on "
                       r"(?P<threads>\d+) threads? at (?P<rate>[0-9.e+-]+) terms/s")
_UNTIMED = re.compile(r"^estimate: (?P<job>.*): no scene sums")
_MEMORY = re.compile(r"^estimate: about (?P<mib>\d+) MiB at the peak")
_state = {"key": None, "text": None, "thread": None}


def frame_size(scene):
    """The rendered frame's pixels, as Blender writes them (resolution times its percentage)."""
    r = scene.render
    return int(r.resolution_x * r.resolution_percentage / 100), int(r.resolution_y * r.resolution_percentage / 100)


def nearest_depth_m(scene, camera_object, depsgraph):
    """The nearest visible depth in metres along the view axis (the depth pass's), from rays
    through the centres of a grid over the frame; inf where every ray meets only the world."""
    width, height = frame_size(scene)
    corners = camera_object.data.view_frame(scene=scene)  # the frame at z = -d in the camera's space
    x0, x1 = min(c.x for c in corners), max(c.x for c in corners)
    y0, y1 = min(c.y for c in corners), max(c.y for c in corners)
    z = corners[0].z
    world = camera_object.matrix_world
    to_camera = world.inverted()
    origin = world.translation
    columns = RAYS_ACROSS
    rows = max(2, round(columns * height / max(1, width)))
    nearest = math.inf
    for j in range(rows):
        for i in range(columns):
            local = Vector((x0 + (i + 0.5) / columns * (x1 - x0), y0 + (j + 0.5) / rows * (y1 - y0), z))
            direction = (world.to_3x3() @ local).normalized()
            hit, location, *_ = scene.ray_cast(depsgraph, origin, direction)
            if hit:
                nearest = min(nearest, -(to_camera @ location).z)
    return nearest * scene.unit_settings.scale_length


def estimate_command(scene, camera_object, depsgraph):
    """The command line for this camera's next frame, or None when the frame cannot be modelled
    (the panel shows why)."""
    exe = wavecam_command()
    camera = RenderedCamera(scene, camera_object)
    if not exe or camera.fov is None or camera.settings_error:
        return None
    width, height = frame_size(scene)
    nearest = nearest_depth_m(scene, camera_object, depsgraph)
    return [exe, "estimate", "--size", f"{width}x{height}",
            "--nearest", "inf" if math.isinf(nearest) else f"{nearest:.6g}m",
            *wavecam_run.setting_flags(camera, fov_in_file=False)]


def estimate_text(command, timeout=120):
    """What the panel says of a job: its time, or why it has none, and any refusal."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"Estimate: none ({e})"
    said = []
    for line in done.stderr.splitlines():
        if m := _ESTIMATE.match(line):
            said.append(f"Estimate: about {m.group('time')} here ({float(m.group('terms')):.3g} terms at "
                        f"{float(m.group('rate')):.3g}/s measured now)")
        elif m := _UNTIMED.match(line):
            said.append("Estimate: no scene sums (a PSF grid and FFTs): seconds to minutes, not timed")
        elif m := _MEMORY.match(line):
            said.append(f"{m.group('mib')} MiB at the peak")
        elif line.startswith("wavecam estimate: "):
            said.append("Would be refused: " + re.sub(r"^wavecam estimate: [^:]*frame: ", "", line))
    return "; ".join(said) if said else f"Estimate: none (wavecam estimate exited with status {done.returncode})"


def _key(scene, camera_object):
    """What the estimate depends on, but for the scene's geometry."""
    w = camera_object.data.wavecam
    settings = tuple(getattr(w, p.identifier) for p in w.bl_rna.properties
                     if p.identifier not in {"rna_type", "name"} and not p.is_readonly)
    return (scene.name, camera_object.name, frame_size(scene), camera_object.data.lens,
            camera_object.data.sensor_width, tuple(map(tuple, camera_object.matrix_world)),
            scene.unit_settings.scale_length, settings)


def _poll():
    thread = _state["thread"]
    if thread is not None and thread.is_alive():
        return 0.25
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'PROPERTIES':
                area.tag_redraw()
    return None


def panel_text(context, camera_object):
    """The estimate for the panel: the last one while it stands (or while Blender renders), else
    a new one started (its text 'Estimating ...' until the command answers)."""
    if bpy.app.is_job_running('RENDER'):  # the depsgraph is not ours to evaluate while Blender renders
        return _state["text"]
    scene = context.scene
    key = _key(scene, camera_object)
    if key == _state["key"]:
        return _state["text"]
    thread = _state["thread"]
    if thread is not None and thread.is_alive():
        return "Estimating ..."
    command = estimate_command(scene, camera_object, context.evaluated_depsgraph_get())
    _state["key"], _state["text"] = key, None if command is None else "Estimating ..."
    if command is None:
        return None

    def run():
        _state["text"] = estimate_text(command)

    _state["thread"] = threading.Thread(target=run, daemon=True)
    _state["thread"].start()
    bpy.app.timers.register(_poll, first_interval=0.25)
    return _state["text"]
