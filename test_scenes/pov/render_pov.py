"""render_pov.sh SCENE.pov|SCENE.ini OUT.exr [--width W --height H] [--fov DEG] [--depth-scale 1cm]
                 [--frames A-B] [POV-Ray options: +Q5, Declare=NAME=VALUE, Initial_Clock=0, user.ini ...]

Renders an unmodified POV-Ray 3.7 scene into the EXR wavecam takes: R, G, B (POV-Ray's own
render of the scene, linear), Z (planar depth along the camera's view axis, 1e10 = sky; in
metres with --depth-scale, else in the scene's units) and wavecam.fov (horizontal field of
view, degrees). See README, "POV-Ray".
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
FRAME_SWITCHES = re.compile(r"[+-](KFI|KFF|SF|EF)", re.I)
IO_KEYS = {"input_file_name": "SCENE", "output_file_name": "OUT", "output_file_type": "OUT (EXR)",
           "output_to_file": "OUT"}
FRAME_KEYS = {"initial_frame", "final_frame", "subset_start_frame", "subset_end_frame"}
PART_KEYS = {"start_row", "end_row", "start_column", "end_column"}



def parse_args(argv):
    p = argparse.ArgumentParser(prog="render_pov.sh", description="Renders an unmodified POV-Ray 3.7 scene into "
                                "the EXR wavecam takes (R, G, B, planar depth Z, wavecam.fov). README: POV-Ray.")
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
    p.add_argument("--frames", help="animation frames A-B (POV-Ray +KFI A +KFF B; the clock runs from +KI to +KF, "
                   "default 0 to 1): one EXR per frame, numbered as OUT's pattern says")
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
    """A length with its unit, as wavecam reads one (core/src/units.cpp): metres, > 0, finite."""
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


def check_output(out, frames):
    """The output is checked before anything runs: an EXR (what the harness writes), in a folder
    that exists, a frame pattern exactly when frames are asked for."""
    if not out.lower().endswith(".exr"):
        raise Refusal(f"{out}: the harness writes OpenEXR only (R, G, B, Z and wavecam's metadata): name the output "
                      "*.exr; wavecam apply --png makes a viewable PNG of the diffracted result")
    if not os.path.isdir(os.path.dirname(out)):
        raise Refusal(f"{out}: its folder does not exist")
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


def check_option(option, where, in_ini=False, frames=None):
    """Refuse an option the harness sets itself on the command line; in an ini (where the
    harness's later options override input and output) only frames without --frames and part
    of the image."""
    frames_text = ("give --frames FIRST-LAST instead (clock options +KI/+KF, Initial_Clock pass through)"
                   if frames is None or not in_ini else None)
    if option[0] in "+-":
        if FRAME_SWITCHES.match(option):
            if frames_text:
                raise Refusal(f"{where}: '{option}' sets the animation's frames: {frames_text}")
        elif OWNED_SWITCHES.match(option) and not (in_ini and IO_SWITCHES.match(option)):
            raise Refusal(f"{where}: '{option}' is set by the harness itself (input, output, EXR, the whole image)")
    elif "=" in option:
        key = option.split("=", 1)[0].strip().lower()
        name = option.split("=", 1)[0].strip()
        if key in FRAME_KEYS and frames_text:
            raise Refusal(f"{where}: '{name}' sets the animation's frames: {frames_text}")
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
                check_option(value if key == "switch" else f"{key}={value}", path, True, args.frames)
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


def resolve_scene(name, frames=None):
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
            check_option(value if key == "switch" else f"{key}={value}", ini, True, frames)
        if not inputs:
            raise Refusal(f"{ini}: the ini names no scene (Input_File_Name=scene.pov)")
        scene = os.path.join(os.path.dirname(ini), inputs[-1])
        return resolve_scene(scene)[0], [quoted(ini)]
    scene = name if name.lower().endswith(".pov") else os.path.join(pov_dir, name + ".pov")
    if not os.path.isfile(scene):
        raise Refusal(f"{scene}: no such POV-Ray scene")
    return os.path.realpath(scene), []


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


def scan_fog_and_media(scene):
    """Refuse a scene whose own text (or a file it #includes from its own folder) has fog,
    participating media (a media block in an object's interior or the global atmosphere) or
    atmosphere: the depth pass adds a fog of its own and reads it back. photons { media on }
    (photon settings in global_settings) is not participating media."""
    seen, todo = set(), [scene]
    while todo:
        path = todo.pop()
        if path in seen or not os.path.isfile(path):
            continue
        seen.add(path)
        text = pov_camera.strip_comments(open(path, errors="replace").read())
        words = re.sub(r'"[^"\n]*"', lambda q: " " * len(q.group(0)), text)  # not inside strings
        words = blank_blocks(words, "photons")
        for m in re.finditer(r"\b(fog|media|atmosphere)\b", words):
            line = text.count("\n", 0, m.start()) + 1
            what = "'media' (participating media)" if m.group(1) == "media" else f"'{m.group(1)}'"
            raise Refusal(f"{path}:{line}: the scene has its own {what}; the depth pass measures "
                          "distance with a fog of its own, which that would change: not supported")
        for inc in re.findall(r'#\s*include\s+"([^"]+)"', text):
            todo.append(os.path.join(os.path.dirname(path), inc))


def globalize_locals(text):
    """The scene's text (comments stripped, lines kept) with its top-level #local made #declare:
    POV-Ray forgets a file's top-level #local once the file is #included, and the camera probe
    #includes the scene (shared/NOTES.md). #local inside a #macro is left alone."""
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
    check_output(out, args.frames)  # first: nothing runs for an output that cannot be written
    scene, ini = resolve_scene(args.scene, args.frames)
    options = ini + user_options(args)
    scan_fog_and_media(scene)
    text = pov_camera.strip_comments(open(scene, errors="replace").read())
    if args.frames is None:
        render_frame(args, scene, text, out, options, [])
        return
    first, last = args.frames
    for frame in range(first, last + 1):
        render_frame(args, scene, text, frame_path(out, frame), options,
                     [f"+KFI{first}", f"+KFF{last}", f"+SF{frame}", f"+EF{frame}"])


if __name__ == "__main__":
    # A terminated run (timeout, Ctrl-C) unwinds too: POV-Ray is killed, temp files go.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    arguments = parse_args(sys.argv[1:])
    try:
        main(arguments)
    except Refusal as e:
        print(f"render_pov.sh: {arguments.scene}: {e}", file=sys.stderr)
        sys.exit(1)
