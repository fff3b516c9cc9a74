# After Blender writes a frame (render_write: -f N, -a, a still rendered with a file), the
# frame's exact field of view goes into its EXR and `wavecam apply` writes NAME.wavecam.exr
# beside it: at once in background mode, else queued and run off the main thread
# (diffraction_queue.py). A still Blender does not write (F12) is saved from the Render Result
# beside the scene's output path first (render_complete with no render_write before it), where
# it stays with its diffracted image after Blender quits.
# Nothing here may raise into Blender: every failure becomes a report.
#
# Every refusal that can be judged before the render (settings_check.py) is made in
# render_init, when the job starts: the message appears before the frame is rendered. Python
# cannot cancel a render, so the job's frames are then left as Blender renders them, and when
# the job ends one message names them all.
#
# The camera "as rendered" is the render depsgraph's evaluated camera (rendered_camera.py):
# frame_change_post runs on that depsgraph before each rendered frame, so the camera is
# captured there, and render_write uses the capture for its frame.
import os

import bpy
from bpy.app.handlers import persistent

from . import command_output, diffraction_queue, exr_fov, reports, settings_check
from .rendered_camera import RenderedCamera
from .wavecam_run import WavecamRunError, run_wavecam

SUFFIX = ".wavecam.exr"


class FrameError(Exception):
    pass


def diffracted_path(frame_path):
    """shot_0001.exr -> shot_0001.wavecam.exr"""
    stem, ext = os.path.splitext(frame_path)
    return (stem if ext.lower() == ".exr" else frame_path) + SUFFIX


def written_frame_path(scene):
    """The file Blender just wrote: an animation frame (-a, -f N, Ctrl+F12) is named by
    frame_path, a still written by render(write_still=True) is the output path itself with the
    format's extension. Where both exist, the newer is the one just written."""
    frame = scene.render.frame_path(frame=scene.frame_current)
    still = bpy.path.abspath(scene.render.filepath)
    if scene.render.use_file_extension:
        stem, ext = os.path.splitext(still)
        still = (stem if ext.lower() in {".exr", ".png", ".jpg", ".jpeg", ".tif", ".tiff"} else still) + ".exr"
    existing = [p for p in (frame, still) if os.path.isfile(p)]
    return max(existing, key=os.path.getmtime) if existing else frame


# (scene name, frame) -> RenderedCamera captured from the render depsgraph
_rendered = {}


def prepare_frame(scene, frame_path, camera=None):
    """Checks and tags one written frame; returns its diffraction job. `camera`: the frame's
    RenderedCamera, by default the one captured for it (else the scene's)."""
    camera = camera or _rendered.pop((scene.name, scene.frame_current), None) or RenderedCamera(scene, scene.camera)
    try:
        settings_check.check_frame(scene, camera)
    except settings_check.SettingError as e:
        raise FrameError(str(e))
    if not os.path.isfile(frame_path):
        raise FrameError(f"{frame_path}: Blender's frame is not there")
    try:
        exr_fov.write_fov(frame_path, camera.fov)
        fov_in_file = True
    except ImportError:  # Blender without OpenImageIO's Python bindings: wavecam is told instead
        fov_in_file = False
    except exr_fov.LossyFile as e:
        reports.info(f"{e}: wavecam is given --fov instead")
        fov_in_file = False
    except exr_fov.TagError as e:
        raise FrameError(str(e))
    return diffraction_queue.Job(scene.name, scene.frame_current, frame_path, diffracted_path(frame_path), camera,
                                 fov_in_file)


def diffract_now(job):
    """Runs `wavecam apply` for the job and waits (background mode), its estimate and progress
    printed as they come; returns the diffracted file's path."""
    def say(line):
        if command_output.device_warning(line):
            reports.warning(f"frame {job.frame}: {command_output.device_warning(line)}")
        if command_output.estimate(line) or command_output.progress(line):
            print(f"wavecam: frame {job.frame}: {line.removeprefix('apply: ')}", flush=True)
    try:
        run_wavecam(job.camera, job.frame_path, job.out_path, job.fov_in_file, on_line=say)
    except WavecamRunError as e:
        raise FrameError(str(e))
    return job.out_path


@persistent
def on_frame_change_post(scene, depsgraph=None):
    try:
        if depsgraph is None or depsgraph.mode != 'RENDER' or scene.camera is None:
            return
        camera_object = scene.camera.evaluated_get(depsgraph)
        if camera_object.type == 'CAMERA' and camera_object.data.wavecam.enabled:
            _rendered[(scene.name, scene.frame_current)] = RenderedCamera(depsgraph.scene_eval, camera_object)
    except Exception as e:  # reported; render_write then falls back to the scene's camera
        reports.error(f"frame {scene.frame_current}: cannot read the rendered camera: {e}")


def _enabled(scene):
    camera_object = scene.camera
    return camera_object is not None and camera_object.type == 'CAMERA' and camera_object.data.wavecam.enabled


def _diffract_reported(scene, frame_path_of, camera=None):
    """Background mode: the frame diffracted now. With a window: queued, diffracted off the
    main thread (diffraction_queue.py)."""
    try:
        job = prepare_frame(scene, frame_path_of(scene), camera)
        if not bpy.app.background:
            diffraction_queue.submit(job)
            return
        out_path = diffract_now(job)
        reports.info(f"frame {scene.frame_current}: wrote {out_path}")
    except FrameError as e:
        reports.error(f"frame {scene.frame_current}: {e}")
    except Exception as e:  # never a crash: anything unforeseen is reported too
        reports.error(f"frame {scene.frame_current}: unexpected failure: {type(e).__name__}: {e}")


def still_folder(scene):
    """Where an F12 still is kept: the folder of the scene's output path (Output > Output); for a
    relative output path in a .blend never saved, ~/wavecam. Never only a temporary folder."""
    if scene.render.filepath.startswith("//") and not bpy.data.filepath:
        return os.path.join(os.path.expanduser("~"), "wavecam")
    return os.path.dirname(bpy.path.abspath(scene.render.frame_path(frame=scene.frame_current)))


def unsaved_still_path(scene):
    """Saves the Render Result (Blender wrote no file) as SCENE_still_FRAME.exr in still_folder;
    its diffracted image is written beside it."""
    folder = still_folder(scene)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"{bpy.path.clean_name(scene.name)}_still_{scene.frame_current:04d}.exr")
    bpy.data.images['Render Result'].save_render(path, scene=scene)
    return path


def _diffract_unsaved_still(scene_name, camera):
    scene = bpy.data.scenes.get(scene_name)
    if scene is not None:
        _diffract_reported(scene, unsaved_still_path, camera)


_written = set()  # scenes whose current render wrote a file
_refused = {}  # scene name -> (the refusal made when its render started, the frames rendered since)


@persistent
def on_render_init(scene, *args):
    _written.discard(scene.name)
    _refused.pop(scene.name, None)
    diffraction_queue.render_started()
    try:
        if _enabled(scene):
            settings_check.check_frame(scene, RenderedCamera(scene, scene.camera))
    except settings_check.SettingError as e:
        _refused[scene.name] = (str(e), [])
        reports.error(f"this render is not diffracted: {e}")
    except Exception as e:
        reports.error(f"frame {scene.frame_current}: unexpected failure: {type(e).__name__}: {e}")


@persistent
def on_render_post(scene, *args):
    if scene.name in _refused:
        _refused[scene.name][1].append(scene.frame_current)


@persistent
def on_render_write(scene, *args):
    _written.add(scene.name)
    if _enabled(scene) and scene.name not in _refused:
        _diffract_reported(scene, written_frame_path)


def _name_refused_frames(scene):
    """Once per render, every frame it left undiffracted, with the reason."""
    why, frames = _refused.pop(scene.name, (None, []))
    if frames:
        s = "s" if len(frames) > 1 else ""
        reports.info(f"frame{s} {', '.join(str(f) for f in frames)} left as Blender rendered {'them' if s else 'it'}, "
                     f"not diffracted: {why}")


@persistent
def on_render_complete(scene, *args):
    try:
        refused = scene.name in _refused
        _name_refused_frames(scene)
        if not refused and scene.name not in _written and _enabled(scene):
            camera = _rendered.pop((scene.name, scene.frame_current), None)
            reports.on_main_thread(_diffract_unsaved_still, scene.name, camera)
    except Exception as e:
        reports.error(f"frame {scene.frame_current}: unexpected failure: {type(e).__name__}: {e}")
    finally:
        _rendered.clear()  # captures of frames never written


@persistent
def on_render_cancel(scene, *args):
    _name_refused_frames(scene)
    _rendered.clear()


_handlers = ((bpy.app.handlers.render_init, on_render_init),
             (bpy.app.handlers.frame_change_post, on_frame_change_post),
             (bpy.app.handlers.render_post, on_render_post),
             (bpy.app.handlers.render_write, on_render_write),
             (bpy.app.handlers.render_complete, on_render_complete),
             (bpy.app.handlers.render_cancel, on_render_cancel))


def register():
    for handlers, handler in _handlers:
        handlers.append(handler)


def unregister():
    for handlers, handler in _handlers:
        if handler in handlers:
            handlers.remove(handler)
    _rendered.clear()
