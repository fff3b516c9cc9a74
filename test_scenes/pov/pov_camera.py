"""The camera of an unmodified POV-Ray 3.7 scene: found in the scene's text, its expressions
evaluated by POV-Ray itself (a wrapper #includes the scene, so identifiers, #if and
image_width mean what they mean in the scene), composed here the way POV-Ray 3.7 composes
them (source/parser/parse.cpp, Parse_Camera, language version >= 3.5: modifiers apply in a
fixed order -- right, direction, angle, up, sky, location, look_at -- then the camera's
transformations in the order written).

Why parse rather than probe: POV-Ray's SDL cannot read the camera back, and a probe render
can only see the scene's surfaces; a render-only probe would need the camera's location to
place anything in front of it. Reading the block and letting POV-Ray evaluate every
expression keeps the scene's own meaning for everything the block uses. What this reads is
then checked against the camera POV-Ray rendered with (fog_depth.check_camera).
"""
import math
import re

import numpy as np

# POV-Ray 3.7's defaults (source/core/scene/camera.cpp, Camera::Init).
DEFAULTS = {"location": (0.0, 0.0, 0.0), "direction": (0.0, 0.0, 1.0), "right": (1.33, 0.0, 0.0),
            "up": (0.0, 1.0, 0.0), "sky": (0.0, 1.0, 0.0)}
VECTOR_MODS = ("location", "direction", "right", "up", "sky", "look_at", "focal_point")
FLOAT_MODS = ("angle", "aperture", "blur_samples", "confidence", "variance")
TRANSFORMS = ("translate", "rotate", "scale", "matrix", "transform")
TYPES = ("perspective", "orthographic", "fisheye", "ultra_wide_angle", "omnimax", "panoramic",
         "cylinder", "spherical", "mesh_camera", "user_defined")
KEYWORDS = set(VECTOR_MODS + FLOAT_MODS + TRANSFORMS + TYPES + ("normal",))


class CameraError(Exception):
    """The camera statement cannot be read here (--fov can stand in for it)."""


class CameraUnusable(CameraError):
    """The camera was read and wavecam cannot use it (not a pinhole): refused."""


def strip_comments(text):
    """SDL text with // and /* */ comments blanked (strings kept, line numbers kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def _block_end(text, open_brace):
    depth = 0
    for k in range(open_brace, len(text)):
        if text[k] == "{":
            depth += 1
        elif text[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    raise CameraError("a camera { block is not closed")


def camera_blocks(text):
    """Bodies of the file's camera statements (outside #declare/#local), the last first (the
    one POV-Ray uses unless #if branches or macros choose), a leading camera identifier
    replaced by its declared body."""
    declared, statements = {}, []
    for m in re.finditer(r"\bcamera\s*\{", text):
        body = text[m.end():_block_end(text, m.end() - 1)]
        decl = re.search(r"#\s*(?:declare|local)\s+(\w+)\s*=\s*$", text[:m.start()])
        if decl:
            declared[decl.group(1)] = body
            continue
        first = re.match(r"\s*(\w+)", body)
        if first and first.group(1) in declared:
            body = declared[first.group(1)] + "\n" + body[first.end():]
        statements.append(body)
    return statements[::-1]


def _items(body):
    """Split a camera body into ('mod', keyword, expression) and ('directive', text) items."""
    items, i, n = [], 0, len(body)
    current = None
    depth = 0
    while i < n:
        c = body[i]
        if depth == 0 and c == "#":
            m = re.match(r"#\s*\w+", body[i:])
            j = i + (m.end() if m else 1)
            k = j
            while k < n and body[k] in " \t":
                k += 1
            if k < n and body[k] == "(":  # #if (cond), #case (value), #while (cond)
                d = 0
                for k2 in range(k, n):
                    d += body[k2] == "("
                    d -= body[k2] == ")"
                    if d == 0:
                        j = k2 + 1
                        break
            elif m and re.match(r"#\s*(declare|local)", m.group(0)):
                j = body.index(";", j) + 1
            elif m and re.match(r"#\s*(debug|warning|error)", m.group(0)):
                q1 = body.index('"', j)
                j = body.index('"', q1 + 1) + 1
            current = None
            items.append(("directive", body[i:j]))
            i = j
            continue
        if c in "({<":
            depth += 1
        elif c in ")}>":
            depth -= 1
        if depth == 0 and (c.isalpha() or c == "_") and (i == 0 or not (body[i - 1].isalnum() or body[i - 1] == "_")):
            m = re.match(r"\w+", body[i:])
            word = m.group(0)
            if word in KEYWORDS:
                if word == "normal":
                    raise CameraUnusable("the camera has a 'normal' (perturbed rays): not a pinhole camera")
                current = ["mod", word, ""]
                items.append(current)
                i += m.end()
                continue
            if current is None:
                raise CameraError(f"cannot read the camera statement at '{word}'")
        if current is not None:
            current[2] += c
        elif not c.isspace():
            raise CameraError(f"cannot read the camera statement at '{body[i:i + 20].strip()}'")
        i += 1
    return items


def probe_sdl(body):
    """SDL that, after the scene, prints each camera modifier's value, one number a line
    ('wavecam-cam KEY INDEX VALUE'; POV-Ray wraps long console lines)."""
    out = []

    def number(key, index, value):
        return f'#debug concat("wavecam-cam {key} {index} ", str({value}, 0, 12), "\\n")'

    for item in _items(body):
        if item[0] == "directive":
            out.append(item[1])
            continue
        _, key, expr = item
        expr = expr.strip()
        if key in VECTOR_MODS:
            out.append(f"#declare Wavecam_V = <0,0,0> + ({expr});")
            out += [number(key, k, f"Wavecam_V.{c}") for k, c in enumerate("xyz")]
        elif key in FLOAT_MODS or key in TYPES:
            out.append(number(key, 0, expr if expr else "0"))
        else:  # a transformation: the images of the origin and the unit vectors
            out.append(f"#ifdef (Wavecam_F) #undef Wavecam_F #end  // functions cannot be redeclared\n"
                       f"#declare Wavecam_F = function {{ transform {{ {key} {expr} }} }}")
            for p, point in enumerate(("0,0,0", "1,0,0", "0,1,0", "0,0,1")):
                out.append(f"#declare Wavecam_V = Wavecam_F({point});")
                out += [number("xform", 3 * p + k, f"Wavecam_V.{c}") for k, c in enumerate("xyz")]
    return "\n".join(out) + "\n"


class Camera:
    """A perspective POV-Ray camera: pixel (i, j) of W x H looks along
    D + x R + y U, x = (i + 0.5)/W - 0.5, y = 0.5 - (j + 0.5)/H (docs/platform_notes.md)."""

    def __init__(self, location, direction, right, up):
        self.location, self.direction, self.right, self.up = (np.array(v, float) for v in (location, direction, right, up))

    def hfov_deg(self):
        # hfov = 2 atan(|R| / (2 |D|)) for R perpendicular to D
        return math.degrees(2 * math.atan(np.linalg.norm(self.right) / (2 * np.linalg.norm(self.direction))))

    def cosines(self, width, height):
        """Cosine of each pixel ray to the view axis D."""
        x = (np.arange(width) + 0.5) / width - 0.5
        y = 0.5 - (np.arange(height) + 0.5) / height
        rays = (self.direction[None, None, :] + x[None, :, None] * self.right[None, None, :]
                + y[:, None, None] * self.up[None, None, :])
        axis = self.direction / np.linalg.norm(self.direction)
        return (rays @ axis) / np.linalg.norm(rays, axis=-1)

    def world_to_camera(self):
        """OpenEXR worldToCamera (row vectors): rows are the world axes in camera coordinates
        (x along R, y along U, z along D), the last row the translation."""
        r, u, d = (v / np.linalg.norm(v) for v in (self.right, self.up, self.direction))
        m = np.zeros((4, 4))
        m[:3, 0], m[:3, 1], m[:3, 2] = r, u, d
        m[3, :3] = [-r @ self.location, -u @ self.location, -d @ self.location]
        m[3, 3] = 1
        return m


def compose(lines):
    """Camera from the probe's 'wavecam-cam KEY VALUES' lines (POV-Ray 3.7's order)."""
    mods, xforms, kind = {}, [], "perspective"
    for line in lines:
        key, index, value = line.split()
        index, value = int(index), float(value)
        if key in TYPES:
            kind = key
        elif key == "xform":
            if index == 0:
                xforms.append(np.zeros(12))
            xforms[-1][index] = value
        else:
            if index == 0:
                mods[key] = np.zeros(3 if key in VECTOR_MODS else 1)
            mods[key][index] = value
    xforms = [t.reshape(4, 3) for t in xforms]
    if kind != "perspective":
        raise CameraUnusable(f"the camera is '{kind}': wavecam needs a perspective (pinhole) camera")
    if mods.get("aperture", [0])[0] > 0:
        raise CameraUnusable("the camera has focal blur (aperture > 0): wavecam needs a pinhole render; "
                          "remove the aperture (wavecam adds the optics)")
    v = {k: np.array(mods.get(k, DEFAULTS[k]), float) for k in DEFAULTS}
    d, r, u, sky, loc = v["direction"], v["right"], v["up"], v["sky"], v["location"]
    if "angle" in mods:
        angle = mods["angle"][0]
        if not 0 < angle < 180:
            raise CameraUnusable(f"camera angle {angle} is outside (0, 180) degrees")
        d = d / np.linalg.norm(d) * (np.linalg.norm(r) / math.tan(math.radians(angle) / 2) / 2)
    if "look_at" in mods:
        dl, ul, rl = np.linalg.norm(d), np.linalg.norm(u), np.linalg.norm(r)
        handedness = np.cross(u, d) @ r
        d = mods["look_at"] - loc
        d = d / np.linalg.norm(d)
        r_new = np.cross(sky, d)
        if np.linalg.norm(r_new) > 1e-10:
            r = r_new / np.linalg.norm(r_new)
        else:
            r = r / np.linalg.norm(r)
        u = np.cross(d, r)
        d = d * dl
        r = r * (rl if handedness > 0 else -rl)
        u = u * ul
    for t in xforms:  # rows: image of the origin, then of x, y, z
        origin, lin = t[0], (t[1:] - t[0])  # lin rows are the images of the unit vectors
        loc = origin + loc @ lin
        d, r, u = d @ lin, r @ lin, u @ lin
    cam = Camera(loc, d, r, u)
    dn, rn, un = (x / np.linalg.norm(x) for x in (d, r, u))
    if max(abs(dn @ rn), abs(dn @ un), abs(rn @ un)) > 1e-6:
        raise CameraUnusable("the camera's direction, right and up vectors are not perpendicular")
    return cam


def standard_camera(hfov_deg, width, height):
    """A centred camera with square pixels and the given horizontal fov (for --fov)."""
    rl = 2 * math.tan(math.radians(hfov_deg) / 2)
    return Camera((0, 0, 0), (0, 0, 1), (rl, 0, 0), (0, rl * height / width, 0))
