"""render_pov.sh SCENE.pov OUT.exr [--width W --height H] [--fov DEG]

Renders an unmodified POV-Ray 3.7 scene into the EXR wavecam takes: R, G, B (POV-Ray's own
render of the scene, linear), Z (planar depth along the camera's view axis, 1e10 = sky) and
wavecam.fov (horizontal field of view, degrees). See README, "POV-Ray".
"""
import argparse
import os
import re
import signal
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

import fog_depth
import pov_camera
from povray_runner import Povray, PovrayFailed, Refusal

SKY_DEPTH = 1e10
RADIANCE_OPTIONS = ["+A0.3", "-J"]  # POV-Ray's antialiasing, without jitter (repeatable)


def parse_args(argv):
    p = argparse.ArgumentParser(prog="render_pov.sh", description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--fov", help="horizontal field of view, e.g. 50deg (only when the scene's camera cannot be read)")
    a = p.parse_args(argv)
    if (a.width is None) != (a.height is None):
        p.error("give both --width and --height, or neither (POV-Ray's default size)")
    for name in ("width", "height"):
        if getattr(a, name) is not None and getattr(a, name) <= 0:
            p.error(f"--{name} must be a positive number of pixels")
    if a.fov is not None:
        m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(deg)?\s*", a.fov)
        if not m or not 0 < float(m.group(1)) < 180:
            p.error(f"--fov {a.fov}: expected an angle in degrees between 0 and 180, e.g. 50deg")
        a.fov = float(m.group(1))
    return a


def scan_fog_and_media(scene):
    """Refuse a scene whose own text (or a file it #includes from its own folder) has fog,
    media or atmosphere: the depth pass adds a fog of its own and reads it back."""
    seen, todo = set(), [scene]
    while todo:
        path = todo.pop()
        if path in seen or not os.path.isfile(path):
            continue
        seen.add(path)
        text = pov_camera.strip_comments(open(path, errors="replace").read())
        words = re.sub(r'"[^"\n]*"', lambda q: " " * len(q.group(0)), text)  # not inside strings
        for m in re.finditer(r"\b(fog|media|atmosphere)\b", words):
            line = text.count("\n", 0, m.start()) + 1
            raise Refusal(f"{path}:{line}: the scene has its own '{m.group(1)}'; the depth pass measures "
                          "distance with a fog of its own, which that would change: not supported")
        for inc in re.findall(r'#\s*include\s+"([^"]+)"', text):
            todo.append(os.path.join(os.path.dirname(path), inc))


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


def write_exr(out, rgb, z, fov, scene, camera):
    """R, G, B, Z and the header wavecam reads; temp file then rename, nothing on failure."""
    spec = oiio.ImageSpec(z.shape[1], z.shape[0], 4, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "Z")
    spec.attribute("wavecam.fov", float(fov))
    spec.attribute("wavecam.depth", "planar")
    spec.attribute("wavecam.scene", os.path.basename(scene))
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


def main(args):
    pov_dir = os.path.dirname(os.path.abspath(__file__))
    scene = args.scene if args.scene.endswith(".pov") else os.path.join(pov_dir, args.scene + ".pov")
    if not os.path.isfile(scene):
        raise Refusal(f"{scene}: no such POV-Ray scene")
    scene = os.path.realpath(scene)
    out = os.path.abspath(args.out)
    if not os.path.isdir(os.path.dirname(out)):
        raise Refusal(f"{out}: its folder does not exist")
    scan_fog_and_media(scene)
    text = pov_camera.strip_comments(open(scene, errors="replace").read())

    # POV-Ray's I/O security ("restricted" in /etc/povray/3.7/povray.conf) reads below the
    # current folder and writes /tmp: run from the scene's folder, passes under /tmp.
    with tempfile.TemporaryDirectory(prefix="render_pov.", dir="/tmp") as tmp:
        pov = Povray(scene, tmp, (args.width, args.height))
        # First: a camera wavecam cannot use is refused before any long render.
        cameras, why = find_cameras(pov, text)
        _, radiance_path = pov.run(None, RADIANCE_OPTIONS, "radiance render")
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
            up_over_right = np.linalg.norm(camera.up) / np.linalg.norm(camera.right)
            if abs(up_over_right / (height / width) - 1) > 0.01:
                raise Refusal(f"the camera's pixels are not square (|up|/|right| = {up_over_right:.4f}, image "
                              f"{height}/{width} = {height / width:.4f}): use right x*image_width/image_height")
            fov = camera.hfov_deg()
            if args.fov is not None and abs(args.fov - fov) > 0.01:
                raise Refusal(f"--fov {args.fov:g} disagrees with the scene's camera ({fov:.4f} deg); leave --fov out")
            cosines = camera.cosines(width, height)
        z = np.where(sky, SKY_DEPTH, d * cosines).astype(np.float32)
        print(f"render_pov.sh: {os.path.basename(scene)} {width}x{height}, fov {fov:.4f} deg, assumed_gamma "
              f"{gamma:.3f}, fog distances {', '.join(f'{D:g}' for D in distances)}, "
              f"{int(sky.sum())} sky pixels, {check}, {pov.runs} POV-Ray runs", file=sys.stderr)
        write_exr(out, radiance.get_pixels(oiio.FLOAT)[..., :3], z, fov, scene, camera)


if __name__ == "__main__":
    # A terminated run (timeout, Ctrl-C) unwinds too: POV-Ray is killed, temp files go.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    arguments = parse_args(sys.argv[1:])
    try:
        main(arguments)
    except Refusal as e:
        print(f"render_pov.sh: {arguments.scene}: {e}", file=sys.stderr)
        sys.exit(1)
