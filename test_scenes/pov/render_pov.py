"""render_pov.sh SCENE.pov|SCENE.ini OUT.exr [--width W --height H] [--fov DEG] [--depth-scale 1cm]
                 [--frames A-B] [POV-Ray options: +Q5, Declare=NAME=VALUE, Initial_Clock=0, user.ini ...]

Renders an unmodified POV-Ray 3.7 scene into the EXR wavecam takes: R, G, B (POV-Ray's own
render of the scene, linear), Z (planar depth along the camera's view axis, 1e10 = sky; in
metres with --depth-scale, else in the scene's units) and wavecam.fov (horizontal field of
view, degrees). See docs/povray.md.
"""
import argparse
import math
import os
import re
import signal
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

import fog_depth
import pov_camera
from povray_runner import Povray, PovrayFailed, Refusal, quoted

SKY_DEPTH = 1e10
RADIANCE_OPTIONS = ["+A0.3", "-J"]  # POV-Ray's antialiasing, without jitter (repeatable); the user's options override
LENGTH_UNITS = {"nm": 1e-9, "um": 1e-6, "\u00b5m": 1e-6, "mm": 1e-3, "cm": 1e-2, "m": 1.0}  # as wavecam's units.cpp
FOV_TOLERANCE_DEG = 0.01
# Options the harness sets itself on every run (input, output, its type, the frame subset, rows and
# columns of the image): refused from the user, on the command line or in an ini file.
# (A user's own ini may name an input and an output: there the harness's later options win, and
# only what it cannot override -- frames without --frames, part of the image -- is refused.)
OWNED_SWITCHES = re.compile(r"[+-](I|O|F|SR|ER|SC|EC)", re.I)
IO_SWITCHES = re.compile(r"[+-](I|O|F)", re.I)
IO_KEYS = {"input_file_name": "SCENE", "output_file_name": "OUT", "output_file_type": "OUT (EXR)",
           "output_to_file": "OUT"}
PART_KEYS = {"start_row", "end_row", "start_column", "end_column"}
# The options that say which frames an animation has and which to render, and where POV-Ray looks
# for #include files, as switches and as ini keys.
READ_SWITCHES = {"KFI": "initial_frame", "KFF": "final_frame", "SF": "subset_start_frame",
                 "EF": "subset_end_frame", "L": "library_path"}
READ_SWITCH = re.compile(r"\+(KFI|KFF|SF|EF|L)(.*)", re.I)
READ_KEYS = set(READ_SWITCHES.values())



def parse_args(argv):
    p = argparse.ArgumentParser(prog="render_pov.sh", description="Renders an unmodified POV-Ray 3.7 scene into "
                                "the EXR wavecam takes (R, G, B, planar depth Z, wavecam.fov). See docs/povray.md.")
    p.add_argument("scene", help="a .pov scene (any case), an .ini naming one (Input_File_Name), or small/default/wide")
    p.add_argument("out", help="the EXR to write; with --frames a pattern: out.#.exr, out.%%04d.exr or out.@@@@.exr")
    p.add_argument("pov_options", nargs="*", metavar="POV-OPTION",
                   help="passed to every POV-Ray run: +Q5, +A0.1, Declare=NAME=VALUE, Initial_Clock=0 (+KI0), "
                        "Final_Clock=2 (+KF2), user.ini ...; options starting with - go after --")
    p.add_argument("--width", type=int, help="image width in pixels (default: POV-Ray's, or the ini's Width)")
    p.add_argument("--height", type=int, help="image height in pixels (give both or neither)")
    p.add_argument("--fov", help="horizontal field of view, e.g. 50deg (only when the scene's camera cannot be read)")
    p.add_argument("--depth-scale", help="how long one scene unit is, e.g. 1cm, 2.54cm, 1m: Z is then written in "
                   "metres (and the scale recorded as wavecam.scene-unit)")
    p.add_argument("--frames", help="animation frames A-B to render, one EXR per frame, numbered as OUT's pattern "
                   "says (+SFA +EFB do the same). An animation whose frames are given (Initial_Frame/Final_Frame, "
                   "+KFI/+KFF) keeps POV-Ray's own frame-to-clock mapping; otherwise the clock runs from +KI to +KF "
                   "(default 0 to 1) over A-B")
    a = p.parse_intermixed_args(argv)
    if (a.width is None) != (a.height is None):
        p.error("give both --width and --height, or neither (POV-Ray's default size)")
    for name in ("width", "height"):
        if getattr(a, name) is not None and getattr(a, name) <= 0:
            p.error(f"--{name} must be a positive number of pixels")
    if a.fov is not None:
        m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(deg)?\s*", a.fov)
        try:
            ok = m is not None and 0 < float(m.group(1)) < 180
        except ValueError:
            ok = False
        if not ok:
            p.error(f"--fov {a.fov}: expected an angle in degrees between 0 and 180, e.g. 50deg")
        a.fov = float(m.group(1))
    if a.depth_scale is not None:
        a.depth_scale = parse_length(a.depth_scale, p)
    if a.frames is not None:
        m = re.fullmatch(r"(\d+)(?:-(\d+))?", a.frames.strip())
        if not m or (m.group(2) is not None and int(m.group(2)) < int(m.group(1))):
            p.error(f"--frames {a.frames}: expected a frame range FIRST-LAST such as 1-3 (or one frame, 5)")
        a.frames = (int(m.group(1)), int(m.group(2) or m.group(1)))
    return a


def parse_length(text, p):
    """A length with its unit, as wavecam reads one (core/src/base/units.cpp): metres, > 0, finite."""
    m = re.fullmatch(r"([0-9.eE+-]+)(nm|um|\u00b5m|mm|cm|m)", text.strip())
    try:
        value = float(m.group(1)) * LENGTH_UNITS[m.group(2)] if m else float("nan")
    except ValueError:
        value = float("nan")
    if not (math.isfinite(value) and value > 0):
        p.error(f"--depth-scale {text}: expected a length > 0 with a unit (nm, um, mm, cm, m): how long one scene "
                "unit is, e.g. 1cm, 2.54cm (inches) or 1m")
    return value


def frame_path(pattern, frame):
    """OUT's frame number pattern filled in as wavecam apply --frames (OpenImageIO) reads it:
    '#' is four digits (each), '@' one digit each, %0Nd N digits. None when OUT has no pattern."""
    folder, name = os.path.split(pattern)
    m = re.search(r"%0?(\d*)d|#+|@+", name)
    if not m:
        return None
    token = m.group(0)
    digits = (4 * len(token) if token[0] == "#" else len(token) if token[0] == "@" else int(m.group(1) or 0))
    return os.path.join(folder, name[:m.start()] + f"{frame:0{digits}d}" + name[m.end():])


def check_output(out):
    """The output is checked before anything runs: an EXR (what the harness writes), in a folder
    that exists."""
    if not out.lower().endswith(".exr"):
        raise Refusal(f"{out}: the harness writes OpenEXR only (R, G, B, Z and wavecam's metadata): name the output "
                      "*.exr; wavecam apply --png makes a viewable PNG of the diffracted result")
    if not os.path.isdir(os.path.dirname(out)):
        raise Refusal(f"{out}: its folder does not exist")


def check_pattern(out, frames):
    """A frame pattern in the output's name exactly when frames are asked for."""
    if frames is not None and frame_path(out, frames[0]) is None:
        raise Refusal(f"{out}: --frames needs a frame number pattern in the output's name (#, @ or %04d, as wavecam "
                      "apply --frames reads them), e.g. out.#.exr")
    if frames is None and frame_path(out, 0) is not None:
        raise Refusal(f"{out}: the name has a frame number pattern (#, @ or %d): give --frames FIRST-LAST")


def read_ini(path):
    """(key, value) options and switches of a POV-Ray ini file (before its first [section]);
    keys lowercased."""
    items = []
    try:
        lines = open(path, errors="replace").read().splitlines()
    except OSError as e:
        raise Refusal(f"{path}: cannot read the ini file ({e.strerror})")
    for line in lines:
        line = line.split(";", 1)[0].strip()
        if line.startswith("["):
            break
        if not line:
            continue
        if line[0] in "+-":
            for switch in line.split():
                items.append(("switch", switch))
        elif "=" in line:
            key, value = line.split("=", 1)
            items.append((key.strip().lower(), value.strip().strip('"')))
    return items


def check_option(option, where, in_ini=False):
    """Refuse an option the harness sets itself on the command line; in an ini (where the
    harness's later options override input and output) only part of the image. (Frame options
    are read by animation_frames.)"""
    if option[0] in "+-":
        if OWNED_SWITCHES.match(option) and not (in_ini and IO_SWITCHES.match(option)):
            raise Refusal(f"{where}: '{option}' is set by the harness itself (input, output, EXR, the whole image)")
    elif "=" in option:
        key = option.split("=", 1)[0].strip().lower()
        name = option.split("=", 1)[0].strip()
        if key in PART_KEYS:
            raise Refusal(f"{where}: '{name}' renders part of the image: the harness renders the whole image")
        if key in IO_KEYS and not in_ini:
            raise Refusal(f"{where}: '{name}' is set by the harness itself: give it as {IO_KEYS[key]}")


def user_options(args):
    """The POV-Ray options given after SCENE OUT, checked, ini files as absolute quoted paths."""
    options = []
    for option in args.pov_options:
        if option.lower().endswith(".ini"):
            path = os.path.abspath(option)
            if not os.path.isfile(path):
                raise Refusal(f"{option}: no such ini file")
            for key, value in read_ini(path):
                check_option(value if key == "switch" else f"{key}={value}", path, True)
            options.append(quoted(path))
        elif option[:1] in "+-" or re.match(r"\w+\s*=", option):
            check_option(option, "option")
            if option[:2].upper() in ("+L", "-L") and not option[2:].startswith('"'):
                option = option[:2] + quoted(os.path.abspath(option[2:]))
            options.append(option)
        else:
            raise Refusal(f"'{option}': not a POV-Ray option (expected +SWITCH, NAME=VALUE such as "
                          "Declare=NAME=VALUE, or an .ini file)")
    return options


def resolve_scene(name):
    """(scene .pov path, ini options): SCENE is a .pov file (any case), an .ini that names one
    with Input_File_Name (relative to the ini's folder), or one of ours."""
    pov_dir = os.path.dirname(os.path.abspath(__file__))
    if name.lower().endswith(".ini"):
        ini = os.path.abspath(name)
        if not os.path.isfile(ini):
            raise Refusal(f"{name}: no such ini file")
        inputs = [v for k, v in read_ini(ini) if k == "input_file_name"]
        inputs += [v[2:].strip('"') for k, v in read_ini(ini) if k == "switch" and v[:2].upper() == "+I"]
        for key, value in read_ini(ini):
            check_option(value if key == "switch" else f"{key}={value}", ini, True)
        if not inputs:
            raise Refusal(f"{ini}: the ini names no scene (Input_File_Name=scene.pov)")
        scene = os.path.join(os.path.dirname(ini), inputs[-1])
        return resolve_scene(scene)[0], [quoted(ini)]
    scene = name if name.lower().endswith(".pov") else os.path.join(pov_dir, name + ".pov")
    if not os.path.isfile(scene):
        raise Refusal(f"{scene}: no such POV-Ray scene")
    return os.path.realpath(scene), []


def read_options(scene, args):
    """[(key, value, where)] of the options in READ_KEYS POV-Ray will read, in its order: SCENE's
    ini, then the options after OUT, each ini file in its place (a later one wins). Library
    folders as absolute paths: given on the command line, from here; in an ini, from the scene's
    folder, where POV-Ray runs."""
    found = []

    def read(option, where, folder):
        m = READ_SWITCH.fullmatch(option) if option[:1] == "+" else None
        key, value = (READ_SWITCHES[m.group(1).upper()], m.group(2)) if m else (
            option.split("=", 1)[0].strip().lower(), option.split("=", 1)[1]) if "=" in option else (None, None)
        if key in READ_KEYS:
            value = value.strip().strip('"')
            found.append((key, os.path.join(folder, value) if key == "library_path" else value, where))

    sources = [args.scene] if args.scene.lower().endswith(".ini") else []
    for option in sources + args.pov_options:
        if option.lower().endswith(".ini"):
            for key, value in read_ini(os.path.abspath(option)):
                read(value if key == "switch" else f"{key}={value}", os.path.abspath(option), os.path.dirname(scene))
        else:
            read(option, "option", os.getcwd())
    return found


def animation_frames(args, options):
    """(the frames to render (FIRST, LAST) or None, each frame's POV-Ray options). --frames, or
    +SF/+EF (Subset_Start_Frame/Subset_End_Frame), say which. An animation whose frames are given
    (Initial_Frame/Final_Frame, +KFI/+KFF) keeps them: POV-Ray maps frame N to its clock as
    `povray scene.ini +SFN +EFN` does. Without them the frames asked for are the animation
    (+KFI FIRST +KFF LAST: the clock from +KI to +KF over them)."""
    last = {key: (value, where) for key, value, where in options}

    def number(key):
        if key not in last:
            return None
        value, where = last[key]
        if not re.fullmatch(r"\s*-?\d+\s*", value):
            raise Refusal(f"{where}: {key.replace('_', ' ')} '{value}': expected a whole frame number (a fraction "
                          "of the animation is not read here: give the frame)")
        return int(value)

    initial, final = number("initial_frame"), number("final_frame")
    start, end = number("subset_start_frame"), number("subset_end_frame")
    frames = args.frames
    if start is not None or end is not None:
        if frames is not None:
            raise Refusal("the frames are given twice (--frames and +SF/+EF, Subset_Start_Frame/Subset_End_Frame): "
                          "give one")
        first = start if start is not None else initial or 1
        frames = (first, end if end is not None else max(first, final or 1))
        if frames[1] < frames[0]:
            raise Refusal(f"+SF/+EF: frames {frames[0]}-{frames[1]}: expected the first frame before the last")
    animated = initial is not None or final is not None
    if frames is None:
        if animated and (final or 1) > (initial or 1):
            raise Refusal(f"an animation of frames {initial or 1}-{final} ({last.get('final_frame', ('', 'option'))[1]}): "
                          "give --frames FIRST-LAST (or +SF/+EF) for the frames to render, one EXR each")
        return None, None
    if not animated:
        return frames, lambda f: [f"+KFI{frames[0]}", f"+KFF{frames[1]}", f"+SF{f}", f"+EF{f}"]
    span = (initial or 1, final or 1)
    if frames[0] < span[0] or frames[1] > span[1]:
        raise Refusal(f"frames {frames[0]}-{frames[1]}: beyond the animation's frames {span[0]}-{span[1]} "
                      "(Initial_Frame, Final_Frame)")
    return frames, lambda f: [f"+SF{f}", f"+EF{f}"]


def blank_blocks(words, keyword):
    """words with the inside of every `keyword { ... }` block blanked (newlines kept)."""
    chars = list(words)
    for m in re.finditer(rf"\b{keyword}\s*\{{", words):
        depth = 0
        for k in range(m.end() - 1, len(words)):
            depth += words[k] == "{"
            depth -= words[k] == "}"
            if depth == 0:
                break
        for j in range(m.end(), k):
            if chars[j] != "\n":
                chars[j] = " "
    return "".join(chars)


def find_include(name, including, scene, libraries):
    """The file POV-Ray opens for `#include "name"`: the name itself if absolute, else the first
    found in the including file's folder, the folder POV-Ray runs in (the scene's) and the
    library folders (+L, Library_Path) in order, as given or with .inc added. None when it is
    none of these (POV-Ray's own include library, or missing: POV-Ray says so)."""
    folders = [""] if os.path.isabs(name) else [os.path.dirname(including), os.path.dirname(scene), *libraries]
    names = [name] + ([name + ".inc"] if not os.path.splitext(name)[1] else [])
    for folder in dict.fromkeys(folders):
        for n in names:
            path = os.path.join(folder, n)
            if os.path.isfile(path):
                return os.path.realpath(path)
    return None


def scan_fog_and_media(scene, libraries=()):
    """Refuse a scene whose own text, or any file it #includes from its folder or a library
    folder (+L, Library_Path), has fog, participating media (a media block in an object's
    interior or the global atmosphere) or atmosphere: the depth pass adds a fog of its own and
    reads it back. photons { media on } (photon settings in global_settings) is not
    participating media. POV-Ray's own include library (colors.inc, textures.inc...) is not
    read: it declares media for scenes to use by name, and places none."""
    seen, todo = set(), [(scene, None)]
    while todo:
        path, parent = todo.pop()
        if path is None or path in seen:
            continue
        seen.add(path)
        text = pov_camera.strip_comments(open(path, errors="replace").read())
        words = re.sub(r'"[^"\n]*"', lambda q: " " * len(q.group(0)), text)  # not inside strings
        words = blank_blocks(words, "photons")
        for m in re.finditer(r"\b(fog|media|atmosphere)\b", words):
            line = text.count("\n", 0, m.start()) + 1
            what = "'media' (participating media)" if m.group(1) == "media" else f"'{m.group(1)}'"
            where = f" (#included by {parent})" if parent else ""
            raise Refusal(f"{path}:{line}{where}: the scene has its own {what}; the depth pass measures "
                          "distance with a fog of its own, which that would change: not supported")
        for inc in re.findall(r'#\s*include\s+"([^"]+)"', text):
            todo.append((find_include(inc, path, scene, libraries), path))


def globalize_locals(text):
    """The scene's text (comments stripped, lines kept) with its top-level #local made #declare:
    POV-Ray forgets a file's top-level #local once the file is #included, and the camera probe
    #includes the scene (docs/platform_notes.md). #local inside a #macro is left alone."""
    words = re.sub(r'"[^"\n]*"', lambda q: " " * len(q.group(0)), text)
    out, pos, blocks = [], 0, []
    for m in re.finditer(r"#\s*(\w+)", words):
        word = m.group(1)
        if word in ("macro", "if", "ifdef", "ifndef", "while", "for", "switch"):
            blocks.append(word)
        elif word == "end" and blocks:
            blocks.pop()
        elif word == "local" and "macro" not in blocks:
            out += [text[pos:m.start()], "#declare"]
            pos = m.end()
    return "".join(out) + text[pos:]


def read_camera(pov, body):
    """The Camera a camera statement's body describes, evaluated by POV-Ray after the scene."""
    sdl = pov_camera.probe_sdl(body)
    try:
        log = pov.parse(sdl, "camera probe")
    except PovrayFailed as e:
        if not e.in_wrapper:
            raise
        raise pov_camera.CameraError("POV-Ray cannot evaluate its camera statement outside the scene "
                                     "(a macro's camera?)")
    lines = [l[len("wavecam-cam "):] for l in log.splitlines() if l.startswith("wavecam-cam ")]
    return pov_camera.compose(lines)


def find_cameras(pov, text):
    """(candidate Cameras, why none): every camera statement of the scene file that reads, the
    last first; the render check picks the one POV-Ray used."""
    try:
        bodies = pov_camera.camera_blocks(text)
    except pov_camera.CameraError as e:
        return [], str(e)
    if not bodies:
        # A camera in an included file or a macro? A second camera makes POV-Ray say so.
        log = pov.parse("camera { }\n", "camera probe")
        if "More than one camera" not in " ".join(log.split()):  # POV-Ray wraps its lines
            raise Refusal("the scene has no camera: POV-Ray would use its default camera (at the origin, "
                          "looking along +z, right 1.33x whatever the image's shape); add a camera { } statement")
        return [], "its camera statement is not in the scene file itself (an included file or a macro)"
    cameras, reasons = [], []
    for body in bodies:
        try:
            cameras.append(read_camera(pov, body))
        except pov_camera.CameraError as e:
            reasons.append(e)
    if not cameras and isinstance(reasons[0], pov_camera.CameraUnusable):
        raise Refusal(str(reasons[0]))
    return cameras, "; ".join(dict.fromkeys(str(r) for r in reasons))


def pick_camera(pov, cameras, d, sky, gamma, width, height):
    """(camera, note): the first candidate that passes the render check, or (None, why)."""
    if not (~sky).any():
        return (cameras[0], "camera not checked (no surface seen)") if cameras else (None, "")
    errors = []
    for camera in cameras:
        nearest = float((d * camera.cosines(width, height))[~sky].min())
        try:
            error, fov_seen = fog_depth.check_camera(pov, camera, width, height, nearest, gamma)
            return camera, f"camera checked (test plane: depth off by {error:.1e} median, fov seen {fov_seen:.3f} deg)"
        except Refusal as e:
            errors.append(str(e))
    return None, errors[0] if errors else ""


def write_exr(out, rgb, z, fov, scene, camera, extra):
    """R, G, B, Z and the header wavecam reads; temp file then rename, nothing on failure."""
    spec = oiio.ImageSpec(z.shape[1], z.shape[0], 4, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "Z")
    spec.attribute("wavecam.fov", float(fov))
    spec.attribute("wavecam.depth", "planar")
    spec.attribute("wavecam.scene", os.path.basename(scene))
    for key, value in extra.items():
        spec.attribute(key, value)
    spec.attribute("compression", "zip")
    if camera is not None:
        spec.attribute("worldToCamera", oiio.TypeDesc("matrix"), camera.world_to_camera().astype(np.float32).ravel())
    partial = os.path.join(os.path.dirname(out), f".{os.path.basename(out)}.partial.exr")
    try:
        image = oiio.ImageOutput.create(partial)
        pixels = np.concatenate([rgb, z[..., None]], axis=-1)
        if not image or not image.open(partial, spec) or not image.write_image(pixels) or not image.close():
            raise Refusal(f"{out}: cannot write: {oiio.geterror()}")
        os.replace(partial, out)
    finally:
        if os.path.exists(partial):
            os.remove(partial)


def square_pixels(camera, width, height):
    up_over_right = np.linalg.norm(camera.up) / np.linalg.norm(camera.right)
    return abs(up_over_right / (height / width) - 1) <= 0.01, up_over_right


def render_frame(args, scene, text, out, options, frame_options):
    # POV-Ray's I/O security ("restricted" in /etc/povray/3.7/povray.conf) reads below the
    # current folder and writes /tmp: run from the scene's folder, passes under /tmp.
    with tempfile.TemporaryDirectory(prefix="render_pov.", dir="/tmp") as tmp:
        pov = Povray(scene, tmp, (args.width, args.height), options, frame_options)
        # The camera probes #include a copy of the scene whose top-level #local are #declare (a
        # top-level #local is gone once its file is #included); lines and relative #includes
        # (POV-Ray runs in the scene's folder) stay as they are.
        copy = globalize_locals(text)
        if copy != text:
            os.mkdir(os.path.join(tmp, "scene"))
            pov.probe_scene = os.path.join(tmp, "scene", os.path.basename(scene))
            with open(pov.probe_scene, "w") as f:
                f.write(copy)
        # First: what the parse tells (the camera, the image's size) is refused before any render.
        cameras, why = find_cameras(pov, text)
        if pov.seen is None:  # no camera probe parsed: the size alone
            pov.parse("", "size probe")
        width, height, clock, frame_number = pov.seen
        if args.width is None:
            pov.size = (width, height)
        if not cameras and args.fov is None:
            raise Refusal(f"cannot read the scene's camera ({why}); pass --fov DEG (its horizontal "
                          "field of view) and the depth assumes a centred camera with square pixels")
        if cameras and args.fov is None and not any(square_pixels(c, width, height)[0] for c in cameras):
            ratio = square_pixels(cameras[0], width, height)[1]
            raise Refusal(f"the camera's pixels are not square (|up|/|right| = {ratio:.4f}, image "
                          f"{height}/{width} = {height / width:.4f}): use right x*image_width/image_height")
        _, radiance_path = pov.run(None, [], "radiance render", defaults=RADIANCE_OPTIONS)
        radiance = oiio.ImageBuf(radiance_path)
        width, height = radiance.spec().width, radiance.spec().height
        pov.size = (width, height)
        d, sky, gamma, distances = fog_depth.depth_passes(pov, fog_depth.FIRST_FOG_DISTANCE)
        camera, check = pick_camera(pov, cameras, d, sky, gamma, width, height)
        if camera is None:
            why = check or why
            if args.fov is None:
                raise Refusal(f"cannot read the scene's camera ({why}); pass --fov DEG (its horizontal "
                              "field of view) and the depth assumes a centred camera with square pixels")
            fov, check = args.fov, "camera given by --fov"
            cosines = pov_camera.standard_camera(fov, width, height).cosines(width, height)
        else:
            square, up_over_right = square_pixels(camera, width, height)
            if not square:
                raise Refusal(f"the camera's pixels are not square (|up|/|right| = {up_over_right:.4f}, image "
                              f"{height}/{width} = {height / width:.4f}): use right x*image_width/image_height")
            fov = camera.hfov_deg()
            if args.fov is not None and abs(args.fov - fov) > FOV_TOLERANCE_DEG:
                raise Refusal(f"--fov {args.fov:g} deg disagrees with the scene's camera, whose horizontal field of "
                              f"view is {fov:.4f} deg (tolerance {FOV_TOLERANCE_DEG} deg); leave --fov out")
            cosines = camera.cosines(width, height)
        z = np.where(sky, SKY_DEPTH, d * cosines)
        extra = {}
        if args.depth_scale is not None:  # metres, as wavecam reads depth; sky stays 1e10
            z = np.where(sky, SKY_DEPTH, z * args.depth_scale)
            extra["wavecam.scene-unit"] = f"{args.depth_scale:g}m"
        if frame_options:
            extra["wavecam.pov-frame"] = frame_number
            extra["wavecam.pov-clock"] = clock
        print(f"render_pov.sh: {os.path.basename(scene)} {width}x{height}, fov {fov:.4f} deg, assumed_gamma "
              f"{gamma:.3f}, fog distances {', '.join(f'{D:g}' for D in distances)}, "
              f"{int(sky.sum())} sky pixels, {check}, "
              + (f"frame {frame_number} clock {clock:g}, " if frame_options else "")
              + (f"depth in metres (1 unit = {args.depth_scale:g} m), " if args.depth_scale is not None
                 else "depth in scene units (wavecam reads metres: --depth-scale), ")
              + f"{pov.runs} POV-Ray runs -> {out}", file=sys.stderr)
        write_exr(out, radiance.get_pixels(oiio.FLOAT)[..., :3], z.astype(np.float32), fov, scene, camera, extra)


def main(args):
    out = os.path.abspath(args.out)
    check_output(out)  # first: nothing runs for an output that cannot be written
    scene, ini = resolve_scene(args.scene)
    options = ini + user_options(args)
    read = read_options(scene, args)
    frames, frame_options = animation_frames(args, read)
    check_pattern(out, frames)
    scan_fog_and_media(scene, [value for key, value, _ in read if key == "library_path"])
    text = pov_camera.strip_comments(open(scene, errors="replace").read())
    if frames is None:
        render_frame(args, scene, text, out, options, [])
        return
    for frame in range(frames[0], frames[1] + 1):
        render_frame(args, scene, text, frame_path(out, frame), options, frame_options(frame))


if __name__ == "__main__":
    # A terminated run (timeout, Ctrl-C) unwinds too: POV-Ray is killed, temp files go.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    arguments = parse_args(sys.argv[1:])
    try:
        main(arguments)
    except Refusal as e:
        print(f"render_pov.sh: {arguments.scene}: {e}", file=sys.stderr)
        sys.exit(1)
