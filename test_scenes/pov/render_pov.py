"""render_pov.sh SCENE.pov OUT.exr [--width W --height H] [--fov DEG]

Renders an unmodified POV-Ray 3.7 scene into the EXR wavecam takes: R, G, B (POV-Ray's own
render of the scene, linear), Z (planar depth along the camera's view axis, 1e10 = sky) and
wavecam.fov (horizontal field of view, degrees). See README, "POV-Ray".
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

import pov_camera

SKY_DEPTH = 1e10
FIRST_FOG_DISTANCE = 10.0  # scene units; the ladder moves up and down from here
LADDER = 4.0           # ratio between successive fog distances
RADIANCE_OPTIONS = ["+A0.3", "-J"]  # POV-Ray's antialiasing, without jitter (repeatable)
FOV_CHECK_DEG = 0.05   # at 64 pixels wide and more (noise measured: <= 0.016 deg at 64x48)
LADDER_STEPS = 6       # at most this many steps up or down from the first distance


class Refusal(Exception):
    pass


class PovrayFailed(Refusal):
    def __init__(self, message, in_wrapper):
        super().__init__(message)
        self.in_wrapper = in_wrapper  # the error is in our added SDL, not in the scene


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
        for m in re.finditer(r"\b(fog|media|atmosphere)\b(?!\s*=)", text):
            line = text.count("\n", 0, m.start()) + 1
            raise Refusal(f"{path}:{line}: the scene has its own '{m.group(1)}'; the depth pass measures "
                          "distance with a fog of its own, which that would change: not supported")
        for inc in re.findall(r'#\s*include\s+"([^"]+)"', text):
            todo.append(os.path.join(os.path.dirname(path), inc))


class Povray:
    def __init__(self, scene, tmp, size):
        self.scene, self.tmp, self.size, self.runs = scene, tmp, size, 0

    def run(self, sdl, options, what):
        """Render the scene itself (sdl None) or a wrapper that #includes it and adds sdl;
        returns (log, exr path or None)."""
        self.runs += 1
        wrapper = self.scene
        if sdl is not None:
            wrapper = os.path.join(self.tmp, f"pass{self.runs}.pov")
            with open(wrapper, "w") as f:
                f.write(f'#include "{self.scene}"\n{sdl}')
        out = os.path.join(self.tmp, f"pass{self.runs}.exr")
        size = [f"+W{self.size[0]}", f"+H{self.size[1]}"] if self.size[0] else []
        cmd = ["povray", "-D", "-V", f"+I{wrapper}", f"+L{os.path.dirname(self.scene)}", *size, *options]
        cmd += ["+FE", f"+O{out}"] if "-F" not in options else []
        proc = subprocess.run(cmd, cwd=os.path.dirname(self.scene), capture_output=True, text=True,
                              errors="replace")
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or (out and "-F" not in options and not os.path.exists(out)):
            message = povray_message(log)
            raise PovrayFailed(f"POV-Ray failed on the {what}:\n{message}",
                               wrapper != self.scene and os.path.basename(wrapper) in message)
        return log, (out if "-F" not in options else None)


def povray_message(log):
    """POV-Ray's own error lines (the file/line and the message)."""
    lines = log.splitlines()
    keep = [i for i, l in enumerate(lines) if re.search(r"error", l, re.I) and "Error Stream" not in l]
    if not keep:
        return "\n".join(lines[-8:])
    picked = []
    for i in keep:
        picked += lines[max(0, i - 1):i + 3]
    return "\n".join(dict.fromkeys(picked))


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise Refusal(f"cannot read POV-Ray's output {path}: {buf.geterror()}")
    return buf.get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)


def find_camera(pov, text):
    """(Camera or None, message): the scene's camera, or None when it cannot be read."""
    body = pov_camera.camera_block(text)
    if body is None:
        # A camera in an included file or a macro? A second camera makes POV-Ray say so.
        log, _ = pov.run("camera { }\n", ["-F", "+SR1", "+ER1", "+SC1", "+EC1"], "camera probe")
        if "More than one camera" not in " ".join(log.split()):  # POV-Ray wraps its lines
            raise Refusal("the scene has no camera: POV-Ray would use its default camera (at the origin, "
                          "looking along +z, right 1.33x whatever the image's shape); add a camera { } statement")
        return None, "its camera statement is not in the scene file itself (an included file or a macro)"
    try:
        sdl = pov_camera.probe_sdl(body)
    except pov_camera.CameraError as e:
        return None, str(e)
    try:
        log, _ = pov.run(sdl, ["-F", "+SR1", "+ER1", "+SC1", "+EC1"], "camera probe")
    except PovrayFailed as e:
        if not e.in_wrapper:
            raise
        return None, "POV-Ray cannot evaluate its camera statement outside the scene (a macro's camera?)"
    lines = [l[len("wavecam-cam "):] for l in log.splitlines() if l.startswith("wavecam-cam ")]
    return pov_camera.compose(lines), ""


def fog_pass(pov, distance, colour):
    # Secondary rays (reflection, refraction, transmission) are cut with adc_bailout 1 (every
    # secondary ray weighs < 1): only the first surface sees the fog, as the depth must.
    sdl = (f"fog {{ distance {distance!r} color rgb {colour} }}\n"
           "global_settings { adc_bailout 1 }\n")
    log, path = pov.run(sdl, ["-A", "+Q9"], f"depth pass (fog distance {distance:g})")
    if "Camera is inside a non-hollow object" in " ".join(log.split()):
        raise Refusal("POV-Ray: \"Camera is inside a non-hollow object. Fog and participating media may not work "
                      "as expected.\" The depth pass relies on fog: make that object hollow")
    return read(path)


def measure_gamma(black, white, grey):
    """POV-Ray 3.7 mixes colours in the scene's assumed_gamma space and writes EXR as its linear
    decoding, value^g. With fog colours 0, 1 and 0.5 the working-space values satisfy
    grey^(1/g) = (black^(1/g) + white^(1/g)) / 2; solve for g where that is well conditioned."""
    ok = (white - black > 0.2) & (white < 0.999) & (grey > black + 0.05)
    if ok.sum() < 10:
        return 1.0
    b, w, m = black[ok], white[ok], grey[ok]
    lo, hi = np.full(b.shape, 0.2), np.full(b.shape, 5.0)
    for _ in range(60):  # f(g) = m^(1/g) - (b^(1/g) + w^(1/g))/2 changes sign once on [0.2, 5]
        g = (lo + hi) / 2
        f = m ** (1 / g) - (b ** (1 / g) + w ** (1 / g)) / 2
        flo = m ** (1 / lo) - (b ** (1 / lo) + w ** (1 / lo)) / 2
        same = np.sign(f) == np.sign(flo)
        lo, hi = np.where(same, g, lo), np.where(same, hi, g)
    return float(np.median((lo + hi) / 2))


def ray_distance(black, white, distance, gamma):
    """(d, u): ray distance d = -D ln(1 - diff) from white - black = 1 - exp(-d/D) (channel
    mean, working space), and u = d / D."""
    diff = (white ** (1 / gamma) - black ** (1 / gamma)).mean(axis=-1)
    t = np.clip(1 - diff, 1e-12, 1)
    u = -np.log(t)
    return u * distance, u


def depth_passes(pov, first_distance):
    """Ray distance per pixel from a ladder of fog distances: each pixel takes the pass with
    d/D nearest 1, where half-float rounding costs least (relative error ~ 2^-11 e^u / u)."""
    passes = {}

    def add(distance):
        black, white = fog_pass(pov, distance, 0), fog_pass(pov, distance, 1)
        passes[distance] = (black, white)

    add(first_distance)
    black, white = passes[first_distance]
    grey = fog_pass(pov, first_distance, 0.5)
    gamma = measure_gamma(black, white, grey)
    sky_u = -math.log(2 ** -10)  # t below 2^-10 (~7 D): nothing finite resolved

    # Up while the farthest pass leaves pixels beyond u = 2.5 and the last step still brought
    # some into range (sky never comes: its t is 0 at any D); down while pixels sit below 0.4.
    for _ in range(LADDER_STEPS):
        top = max(passes)
        far = ray_distance(*passes[top], top, gamma)[1] > 2.5
        if not far.any():
            break
        add(top * LADDER)
        if not (far & (ray_distance(*passes[top * LADDER], top * LADDER, gamma)[1] < sky_u)).any():
            break
    for _ in range(LADDER_STEPS):
        bottom = min(passes)
        u = ray_distance(*passes[bottom], bottom, gamma)[1]
        if not ((u < 0.4) & (u > 0)).any():
            break
        add(bottom / LADDER)
    est = {D: ray_distance(b, w, D, gamma) for D, (b, w) in passes.items()}
    distances = sorted(est)
    d_all = np.stack([est[D][0] for D in distances])
    u_all = np.stack([est[D][1] for D in distances])
    cost = np.where(u_all > 0, np.exp(u_all) / np.maximum(u_all, 1e-12), np.inf)
    best = np.argmin(cost, axis=0)
    d = np.take_along_axis(d_all, best[None], 0)[0]
    sky = u_all[-1] >= sky_u
    # Consistency: where two passes both resolve a pixel well, they must agree; they do not
    # when shading depends on the fog (the scene's own fog or media, light through surfaces).
    worst = 0.0
    for k in range(len(distances) - 1):
        both = (u_all[k] > 0.3) & (u_all[k] < 3) & (u_all[k + 1] > 0.3) & (u_all[k + 1] < 3)
        if both.sum() > 10:
            worst = max(worst, float(np.median(np.abs(d_all[k][both] / d_all[k + 1][both] - 1))))
    if worst > 0.01:
        raise Refusal(f"the depth passes disagree (median {worst:.1%} between fog distances): the scene's "
                      "colours change with the added fog (its own fog or media?); depth would be wrong")
    if (d[~sky] <= 0).any():
        raise Refusal("the added fog does not reach some surfaces (is the camera inside a non-hollow object?)")
    return d, sky, gamma, distances


def verify_camera(pov, camera, width, height, nearest, gamma):
    """Check the camera read from the text against the one POV-Ray renders with: a black plane
    across the view axis at eps (1% of the nearest depth, so in front of everything) and a
    white fog of distance eps; every pixel's planar depth must come back as eps."""
    eps = 0.01 * nearest
    axis = camera.direction / np.linalg.norm(camera.direction)
    offset = float(axis @ camera.location) + eps
    n = ", ".join(repr(float(-c)) for c in axis)
    sdl = (f"plane {{ <{n}>, {-offset!r} hollow no_shadow pigment {{ rgb 0 }}\n"
           "  finish { ambient 0 diffuse 0 specular 0 phong 0 reflection 0 } }\n"
           f"fog {{ distance {eps!r} color rgb 1 }}\n"
           "global_settings { adc_bailout 1 }\n")
    white = read(pov.run(sdl, ["-A", "+Q9"], "camera check")[1])
    d, _ = ray_distance(np.zeros_like(white), white, eps, gamma)
    cos_model, cos_seen = camera.cosines(width, height), np.clip(eps / d, 1e-6, 1)
    offset_error = float(np.median(np.abs(d * cos_model / eps - 1)))
    # The field: tan^2 of each ray's angle to the axis scales as 1/|D|^2; fit the scale k
    # (tan^2 seen = k tan^2 model) and compare the horizontal fov it implies.
    t2_model, t2_seen = 1 / cos_model ** 2 - 1, 1 / cos_seen ** 2 - 1
    k = float((t2_model * t2_seen).sum() / (t2_model ** 2).sum())
    fov = camera.hfov_deg()
    fov_seen = math.degrees(2 * math.atan(math.tan(math.radians(fov) / 2) * math.sqrt(k)))
    if offset_error > 2e-3 or abs(fov_seen - fov) > FOV_CHECK_DEG * max(1, 64 / width):
        raise Refusal(f"the camera read from the scene's text does not match the one POV-Ray renders with (a test "
                      f"plane's planar depth is off by {offset_error:.2%}; fov {fov:.3f} deg read, {fov_seen:.3f} "
                      "deg seen); pass --fov DEG to use a centred camera instead")
    return offset_error, fov_seen


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


def main(argv):
    args = parse_args(argv)
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
        try:  # first: a camera wavecam cannot use is refused before any long render
            camera, why = find_camera(pov, text)
        except pov_camera.CameraError as e:
            raise Refusal(str(e))
        _, radiance_path = pov.run(None, RADIANCE_OPTIONS, "radiance render")
        radiance = oiio.ImageBuf(radiance_path)
        width, height = radiance.spec().width, radiance.spec().height
        pov.size = (width, height)
        if camera is not None:
            up_over_right = np.linalg.norm(camera.up) / np.linalg.norm(camera.right)
            if abs(up_over_right / (height / width) - 1) > 0.01:
                raise Refusal(f"the camera's pixels are not square (|up|/|right| = {up_over_right:.4f}, image "
                              f"{height}/{width} = {height / width:.4f}): use right x*image_width/image_height")
        d, sky, gamma, distances = depth_passes(pov, FIRST_FOG_DISTANCE)

        check = "camera given by --fov"
        if camera is not None and (~sky).any():
            nearest = float((d * camera.cosines(width, height))[~sky].min())
            try:
                error, fov_seen = verify_camera(pov, camera, width, height, nearest, gamma)
                check = f"camera checked (test plane: depth off by {error:.1e} median, fov seen {fov_seen:.3f} deg)"
            except Refusal as e:
                if args.fov is None:
                    raise
                camera, why = None, str(e)
        if camera is None:
            if args.fov is None:
                raise Refusal(f"cannot read the scene's camera ({why}); pass --fov DEG (its horizontal "
                              "field of view) and the depth assumes a centred camera with square pixels")
            fov = args.fov
            cosines = pov_camera.standard_camera(fov, width, height).cosines(width, height)
        else:
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
    try:
        main(sys.argv[1:])
    except Refusal as e:
        print(f"render_pov.sh: {sys.argv[1] if len(sys.argv) > 1 else ''}: {e}", file=sys.stderr)
        sys.exit(1)
