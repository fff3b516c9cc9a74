# The add-on with Blender's UI (run under xvfb-run by blender_addon_test.sh ui, with
# --enable-event-simulate so that the test can press Esc), where diffraction runs off the main
# thread. A timer ticking every 0.05 s records when it ran: while wavecam's command runs (and no
# render job does), no gap between ticks may be much longer than Blender's own pauses (Blender
# responsive; see MAX_GAP_S). Phases:
#   panel:     a refusal too long for a row is drawn as wrapped rows that fit the Properties
#              editor at its default width.
#   still:     F12 (convolution), no file written: the diffracted frame saved, made, reported
#              ("wrote ..." read back from the Info editor's log) and shown, its fov the camera's;
#              on screen it looks as the Render Result does (the same view transform): the
#              centre's displayed colour of each, read from screenshots of the render window.
#   estimate:  random-phase (256 runs) chosen: the panel shows the job's estimate before the render
#              (`wavecam estimate` on the frame's description, off the main thread).
#   progress:  F12 with random-phase (256 runs; Esc ends it): the command's estimate in the Info log, its
#              progress ("42% after ...") in the status bar; then Esc: the command ends, no
#              file (nor the command's temporary) is left, the still phase's result is kept as
#              it was (beside the output path, not in a temporary folder), the cancel reported.
#   refused:   F12 with an Orthographic camera: refused in the Info log, the frame named as left
#              undiffracted, and no diffraction started nor file written.
#   animation: Ctrl+F12, two frames (lens 35 -> 60 mm): both diffracted, each with its fov.
# Screenshots of each phase go to $WAVECAM_UI_SCREENSHOTS when set.
import math
import os
import time

import bpy
import OpenImageIO as oiio

from wavecam_blender import diffraction_queue, job_estimate, panel, progress_display, wrapped_label

# Blender's own redraws under xvfb (software OpenGL, cores shared with builds) pause the main
# thread too, up to about 2 s under load with nothing running; so a pause while wavecam runs
# may be as long as MAX_GAP_S or 1.5 times the longest seen with nothing running, whichever
# is longer (the idle gaps outside setup and panel can be short while a pause under load is
# not: 1.3 s measured while wavecam ran under a full test run's load, the longest idle gap
# 0.79 s). A diffraction on the main thread pauses it for the whole run: the
# progress phase's run lasts 3.5 times that limit before Esc, or the test cannot tell.
MAX_GAP_S = 2.0
LIMIT_S = 200
start = time.time()
state = {"phase": "setup", "since": time.time()}
ticks = []  # (time, wavecam's command running (None: Blender's render job runs), phase)
screens = os.environ.get("WAVECAM_UI_SCREENSHOTS")


def finish(code, message):
    print(message, flush=True)
    os._exit(code)  # quit now, from inside a timer, with the status


def fail(message):
    finish(1, f"FAIL: {state['phase']}: {message}")


def running():
    return diffraction_queue.running_pid() is not None or bool(diffraction_queue.stopping_pids())


def ticker():
    rendering = bpy.app.is_job_running('RENDER')
    ticks.append((time.monotonic(), None if rendering else running(), state["phase"]))
    return 0.05


def longest_gap(while_running=True):
    """The longest time between two ticks while the command was running and Blender's own
    render job was not (it pauses the main thread itself, command or not), and the ticks
    counted then; while_running=False: the same with neither running, for comparison."""
    gaps = sorted(((b[0] - a[0], a[2]) for a, b in zip(ticks, ticks[1:]) if a[1] == while_running), reverse=True)
    print(f"ui: the longest gaps between ticks while wavecam {'ran' if while_running else 'did not run'}: "
          f"{', '.join(f'{g:.3f} s ({phase})' for g, phase in gaps[:5])}", flush=True)
    return (gaps[0][0] if gaps else None), len(gaps)


def screenshot(name, window=None):
    if not screens:
        return
    window = window or bpy.context.window_manager.windows[0]
    os.makedirs(screens, exist_ok=True)
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.screen.screenshot(filepath=os.path.join(screens, name))


def displayed_centre(window, area, name):
    """The colour drawn at the centre of the image `area` shows (8-bit RGB, the mean of 3 x 3
    screen pixels), from a screenshot of its window."""
    path = os.path.join(screens or bpy.app.tempdir, name)
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.screen.screenshot(filepath=path)
    pixels = oiio.ImageBuf(path).get_pixels(oiio.FLOAT)
    region = next(r for r in area.regions if r.type == 'WINDOW')
    x, y = region.view2d.view_to_region(0.5, 0.5, clip=False)  # the image's centre
    row, column = pixels.shape[0] - 1 - (region.y + y), region.x + x
    block = pixels[row - 1:row + 2, column - 1:column + 2, :3]
    return [round(float(block[..., c].mean()) * 255) for c in range(3)]


def compare_display():
    """The diffracted image and the Render Result through the same view, one step a tick (each
    screenshot after a redraw): their centres' displayed colours within 3 levels of 255 (the
    data agree to about 0.5%); the Standard view's, as the image was shown before, for the record
    (112 against the Render Result's 118 here: outside that bound)."""
    window = front_window()
    area = next(a for a in window.screen.areas if a.type == 'IMAGE_EDITOR')
    space = area.spaces.active
    step = state.setdefault("display", [])
    if "drawn" not in state:  # the image just shown: drawn, and a first screenshot (black under xvfb) taken
        state["drawn"] = True
        displayed_centre(window, area, "display_first.png")
    elif len(step) == 0:
        state["shown_image"] = space.image
        step.append(displayed_centre(window, area, "display_diffracted.png"))
        space.image = bpy.data.images['Render Result']
    elif len(step) == 1:
        step.append(displayed_centre(window, area, "display_render_result.png"))
        space.image = state["shown_image"]
        space.image.use_view_as_render = False
    elif len(step) == 2:
        step.append(displayed_centre(window, area, "display_standard_view.png"))
        space.image.use_view_as_render = True
        diffracted, render, standard = step
        print(f"ui: displayed at the centre: diffracted {tuple(diffracted)}, Render Result {tuple(render)}, "
              f"the diffracted through the Standard view {tuple(standard)}", flush=True)
        if max(abs(a - b) for a, b in zip(diffracted, render)) > 3:
            fail(f"the diffracted image is displayed as {diffracted}, the Render Result as {render}")
        return None
    area.tag_redraw()
    return 1.0


def front_window():
    windows = list(bpy.context.window_manager.windows)
    return next((w for w in reversed(windows) if w.screen.is_temporary), windows[-1])


def shown_wavecam_image():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            image = area.spaces.active.image if area.type == 'IMAGE_EDITOR' else None
            if image is not None and image.filepath.endswith(".wavecam.exr"):
                return bpy.path.abspath(image.filepath)
    return None


def fov_of(path):
    source = oiio.ImageInput.open(path)
    return source.spec().getattribute("wavecam.fov") if source else None


def true_fov(lens):  # the scene's landscape frame, sensor fit Auto
    return math.degrees(2 * math.atan(bpy.context.scene.camera.data.sensor_width / 2 / lens))


def check_fov(path, lens, what):
    fov, truth = fov_of(path), true_fov(lens)
    if fov is None or abs(fov - truth) >= 0.01:
        fail(f"{what}: {path} wavecam.fov {fov}, camera {truth:.4f}")
    print(f"{what}: {path}, wavecam.fov {fov:.4f} (camera {truth:.4f})", flush=True)


def info_log():
    """Every line of the Info editor's log (the reports the status bar showed), via the clipboard."""
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'INFO')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
        bpy.ops.info.select_all(action='SELECT')
        bpy.ops.info.report_copy()
    return bpy.context.window_manager.clipboard.splitlines()


def logged(text):
    return [line for line in info_log() if text in line]


def render(animation):
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.render.render('INVOKE_DEFAULT', animation=animation)


def properties_area():
    window = bpy.context.window_manager.windows[0]
    return next(a for a in window.screen.areas if a.type == 'PROPERTIES')


def scroll_properties_down():
    """The wavecam panel is the last of the camera's: scrolled into view for the screenshots."""
    window, area = bpy.context.window_manager.windows[0], properties_area()
    region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
        for _ in range(40):
            bpy.ops.view2d.scroll_down(deltax=0, deltay=50)


def still_path():
    """Where an F12 still's diffracted image is kept: beside the scene's output path."""
    scene = bpy.context.scene
    folder = os.path.dirname(bpy.path.abspath(scene.render.frame_path(frame=scene.frame_current)))
    return os.path.join(folder, f"{bpy.path.clean_name(scene.name)}_still_{scene.frame_current:04d}.wavecam.exr")


def next_phase(name):
    state["phase"], state["since"] = name, time.time()
    print(f"ui: phase {name}", flush=True)


def setup():
    scene = bpy.context.scene
    window = bpy.context.window_manager.windows[0]
    # the camera's data tab in the Properties editor, so the wavecam panel draws (a failing
    # draw prints a Python traceback, which the test looks for)
    bpy.context.view_layer.objects.active = scene.camera
    properties_area().spaces.active.context = 'DATA'
    # the timeline becomes an Info editor, whose log the test reads
    next(a for a in window.screen.areas if a.type == 'DOPESHEET_EDITOR').type = 'INFO'
    w = scene.camera.data.wavecam
    w.auto_pinhole = False
    w.pinhole = 40  # wider than the film: a refusal longer than a row
    next_phase("panel")


def check_panel():
    """The refusal the panel shows, broken as the panel breaks it at the Properties editor's
    width: several rows, each narrower than the editor, the words all there in order."""
    scene = bpy.context.scene
    refusal = panel.problem(scene, scene.camera)
    if not refusal or "wider than the film" not in refusal:
        fail(f"the panel shows no refusal for a 40 mm pinhole: {refusal}")
    text = f"Not diffracted: {refusal}"
    region = next(r for r in properties_area().regions if r.type == 'WINDOW')
    width = wrapped_label.available_width(region.width, icon=True, box=True)
    rows = wrapped_label.rows(text, width)
    widest = max(wrapped_label.text_width(r) for r in rows)
    if len(rows) < 2 or widest > width or " ".join(rows) != " ".join(text.split()):
        fail(f"'{text}' ({wrapped_label.text_width(text):.0f} px) at {region.width} px: rows {rows}, widest "
             f"{widest:.0f} px of {width:.0f}")
    print(f"ui: panel: a {wrapped_label.text_width(text):.0f} px refusal drawn as {len(rows)} rows of at most "
          f"{widest:.0f} px in a {region.width} px Properties editor", flush=True)
    scroll_properties_down()


def tick():
    scene = bpy.context.scene
    w = scene.camera.data.wavecam
    phase = state["phase"]
    if time.time() - start > LIMIT_S:
        fail(f"not done within {LIMIT_S} s; Info log: {info_log()}")
    if phase == "setup":
        setup()
    elif phase == "panel":
        if "checked" not in state:
            check_panel()
            state["checked"] = True
            return 1.0  # the panel redrawn, scrolled
        screenshot("panel_refusal.png")
        w.auto_pinhole = True
        next_phase("still")
        render(animation=False)
    elif bpy.app.is_job_running('RENDER'):
        # nothing touched while a render job runs or winds down (a refused render's job still
        # cancelling when the Info log was read and the next render started crashed Blender
        # under load)
        return 0.5
    elif phase == "still" and (shown_wavecam_image() or "display" in state):  # (the Render Result shown a while)
        if "wrote" not in state:
            check_fov(shown_wavecam_image(), 35, "F12 still shown in an Image Editor")
            state["wrote"] = time.time()
        if not logged("wavecam: frame 1: wrote "):
            if time.time() - state["wrote"] > 10:
                fail(f"no 'wavecam: frame 1: wrote' in the Info log: {info_log()}")
            return 0.5
        if compare_display():
            return 1.0
        print(f"Info log: {logged('wavecam: frame 1: wrote ')[0]}", flush=True)
        if shown_wavecam_image() != still_path():
            fail(f"the F12 still was kept at {shown_wavecam_image()}, expected {still_path()}")
        state["still_kept"] = os.path.getmtime(still_path())
        # (256 runs: the job must outlast the progress phase's checks on a loaded machine, where
        # 64 runs once ended before them; Esc ends it)
        w.method, w.auto_runs, w.runs = 'random-phase', False, 256
        next_phase("estimate")
    elif phase == "estimate":  # the panel's estimate, before the render
        properties_area().tag_redraw()
        text = job_estimate._state["text"] or ""
        if not text.startswith("Estimate: about"):
            if time.time() - state["since"] > 60:
                fail(f"the panel shows no estimate for 256 runs: {text!r}")
            return 0.5
        if "estimate_shown" not in state:
            print(f"ui: panel: {text}", flush=True)
            state["estimate_shown"] = True
            scroll_properties_down()
            return 1.0  # the panel redrawn, scrolled
        screenshot("panel_estimate.png")
        next_phase("progress")
        render(animation=False)
    elif phase == "progress":
        return progress(w)
    elif phase == "cancelled":
        return cancelled(w)
    elif phase == "refused":
        return refused(scene)
    elif phase == "animation":
        last = scene.render.frame_path(frame=2)[:-4] + ".wavecam.exr"
        if shown_wavecam_image() == last and not running():
            check_fov(scene.render.frame_path(frame=1)[:-4] + ".wavecam.exr", 35, "Ctrl+F12 frame 1")
            check_fov(last, 60, "Ctrl+F12 frame 2 shown in an Image Editor")
            screenshot("animation_main.png")
            screenshot("animation_render_window.png", front_window())
            check_responsive()
            finish(0, "ui: passed")
    return 0.5


def gap_limit():
    """(Not counting the setup and panel phases: the test's own work pauses Blender there.)"""
    idle = [b[0] - a[0] for a, b in zip(ticks, ticks[1:]) if a[1] is False and a[2] not in ("setup", "panel")]
    return max([MAX_GAP_S] + [1.5 * g for g in idle])


def progress_run_s():
    ran = [t for t, running, phase in ticks if running and phase == "progress"]
    return ran[-1] - ran[0] if ran else 0


def check_responsive():
    longest_gap(while_running=False)
    limit = gap_limit()
    gap, count = longest_gap()
    if gap is None or gap > limit:
        fail(f"the longest pause of Blender's main thread while wavecam ran was {gap} s (over {count} ticks); "
             f"expected at most {limit:.3f} s")
    if progress_run_s() < 3 * limit:
        fail(f"the progress phase's run lasted {progress_run_s():.1f} s, too short to tell a pause of "
             f"{limit:.3f} s from a blocked main thread")
    print(f"ui: responsive: {count} ticks while wavecam ran (the progress phase's run {progress_run_s():.1f} s), "
          f"the longest gap {gap:.3f} s, at most {limit:.3f} s allowed", flush=True)


def progress(w):
    """The random-phase frame runs: progress in the status bar, then Esc."""
    text = progress_display.shown()
    if text and "%" in text:
        state.setdefault("progress", text)
    if "progress" not in state or diffraction_queue.running_pid() is None:
        if time.time() - state["since"] > 90:
            fail(f"no progress in the status bar within 90 s (last: {text}); Info log: {info_log()}")
        return 0.1
    estimate = logged("wavecam: frame 1: ") and [line for line in logged(" terms, about ") if "Esc cancels" in line]
    if not estimate:
        fail(f"no estimate in the Info log: {info_log()}")
    if "shot" not in state:  # the status bar and panel drawn with the progress
        state["shot"] = True
        return 1.0
    if progress_run_s() < 3.5 * gap_limit():  # long enough to tell a blocked main thread
        return 0.2
    print(f"Info log: {estimate[0]}", flush=True)
    print(f"ui: status bar: {state['progress']}", flush=True)
    # a bar with a cancel cross drawn into Blender's status bar, its width fixed; the headers Blender's
    wm = bpy.context.window_manager
    drawn = [f for f in bpy.types.STATUSBAR_HT_header._dyn_ui_initialize() if f.__module__.endswith("progress_display")]
    if not drawn or not 0 <= wm.wavecam_progress <= 100 or not progress_display.bar_text().startswith("wavecam: frame 1"):
        fail(f"no progress bar in the status bar: {drawn}, {wm.wavecam_progress}, '{progress_display.bar_text()}'")
    print(f"ui: progress bar: '{progress_display.bar_text()}' at {wm.wavecam_progress:.0f}%, "
          f"{progress_display.BAR_UNITS} units wide, a cancel cross beside it", flush=True)
    screenshot("progress_main.png")
    screenshot("progress_render_window.png", front_window())
    state["pid"] = diffraction_queue.running_pid()
    window = front_window()
    window.event_simulate(type='ESC', value='PRESS')
    window.event_simulate(type='ESC', value='RELEASE')
    next_phase("cancelled")
    return 0.1


def cancelled(w):
    pid = state["pid"]
    if os.path.exists(f"/proc/{pid}"):
        if time.time() - state["since"] > 5:
            fail(f"wavecam (pid {pid}) still runs 5 s after Esc")
        return 0.1
    said = logged("wavecam: Esc: frame 1 not diffracted; no file written")
    if not said:
        if time.time() - state["since"] > 10:
            fail(f"no cancel in the Info log: {info_log()}")
        return 0.2
    folder = os.path.dirname(still_path())
    left = [f for f in os.listdir(folder) if ".tmp" in f]
    if left:
        fail(f"temporaries left in {folder} after Esc: {left}")
    if not os.path.isfile(still_path()) or os.path.getmtime(still_path()) != state["still_kept"]:
        fail(f"the earlier still's result {still_path()} was not kept as it was after Esc")
    if shown_wavecam_image() and not os.path.isfile(shown_wavecam_image()):
        fail(f"the Image Editor shows a missing file after Esc: {shown_wavecam_image()}")
    if diffraction_queue.busy() or progress_display.shown():
        fail(f"still busy after Esc: {progress_display.shown()}")
    print(f"Info log: {said[0]}; wavecam (pid {pid}) ended {time.time() - state['since']:.1f} s after Esc, "
          f"no file left, the earlier still kept", flush=True)
    w.method = 'convolution'
    bpy.context.scene.camera.data.type = 'ORTHO'
    next_phase("refused")
    render(animation=False)
    return 0.5


def refused(scene):
    if running() or os.path.getmtime(still_path()) != state["still_kept"]:
        fail("a refused camera's frame is diffracted")
    said = logged("this render is not diffracted: camera 'Camera' is Orthographic")
    named = logged("frame 1 left as Blender rendered it, not diffracted")
    if not said or not named:
        if time.time() - state["since"] > 30:
            fail(f"no refusal naming Orthographic and frame 1 in the Info log: {info_log()}")
        return 0.5
    if "popup" not in state:
        state["popup"] = True
        return 0.5  # the popup drawn
    screenshot("refused_popup.png", front_window())
    print(f"Info log: {said[0]}\nInfo log: {named[0]}", flush=True)
    scene.camera.data.type = 'PERSP'
    next_phase("animation")
    render(animation=True)
    return 0.5


def retried_tick():
    """tick, tried again a moment later where Blender refuses an operator at that moment (the Info
    log's copy while it draws or finishes a render, even from a timer: seen in a CI run)."""
    try:
        return tick()
    except RuntimeError as e:
        if "in this state" not in str(e):
            raise
        print(f"ui: Blender refused an operator for now ({e}); the step again in 0.2 s", flush=True)
        return 0.2


bpy.app.timers.register(ticker, first_interval=0.05)
bpy.app.timers.register(retried_tick, first_interval=3.0)
