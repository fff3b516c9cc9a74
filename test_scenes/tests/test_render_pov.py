"""render_pov.sh on unmodified POV-Ray scenes: radiance is POV-Ray's own render (not
mirrored), depth is the true planar depth (analytic scene, geometry computed here), fov is
the camera's; every refusal exits non-zero, says why and leaves nothing behind.
Run: /usr/bin/python3 test_render_pov.py SCENES_DIR (ctest: render_pov_*)."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import OpenImageIO as oiio

SCENES = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
RENDER = os.path.join(SCENES, "pov", "render_pov.sh")
EXAMPLES = "/usr/share/doc/povray/examples/advanced"
W, H = 64, 48


def render(scene, out, *extra):
    proc = subprocess.run([RENDER, scene, out, *extra], capture_output=True, text=True)
    return proc.returncode, proc.stdout + proc.stderr


def read(path):
    buf = oiio.ImageBuf(path)
    return buf.spec(), buf.get_pixels(oiio.FLOAT)


# Analytic scene: floor y = 0, a sphere, a wall rectangle (z = 6, |x| <= 3, 0 <= y <= 2.5),
# sky above. A reflective sphere and assumed_gamma 2.2 exercise the fog pass's guards.
LOC, LOOK, ANGLE = np.array([0.4, 1.3, -4.0]), np.array([0.6, 0.9, 2.0]), 55.0
SPHERE_C, SPHERE_R = np.array([0.9, 0.8, 1.5]), 0.8
ANALYTIC = f"""#version 3.7;
global_settings {{ assumed_gamma 2.2 }}
camera {{ location <{LOC[0]}, {LOC[1]}, {LOC[2]}> right x*image_width/image_height angle {ANGLE}
         look_at <{LOOK[0]}, {LOOK[1]}, {LOOK[2]}> }}
light_source {{ <-3, 8, -6> rgb 1 }}
sky_sphere {{ pigment {{ rgb <0.3, 0.5, 0.9> }} }}
plane {{ y, 0 pigment {{ checker rgb 0.8 rgb 0.3 }} }}
box {{ <-3, 0, 6>, <3, 2.5, 6.5> pigment {{ rgb <0.2, 0.6, 0.3> }} }}
sphere {{ <{SPHERE_C[0]}, {SPHERE_C[1]}, {SPHERE_C[2]}>, {SPHERE_R} pigment {{ rgb <0.8, 0.2, 0.1> }}
         finish {{ reflection 0.4 }} }}
"""


def look_at_rays(loc, look, angle):
    """Unit pixel rays (H, W, 3) and the view axis of POV-Ray's camera `location loc
    right x*image_width/image_height angle angle look_at look` (sky y), written out here:
    axis f, R = (y x f) * W/H, U = f x R (unit), D = f * (W/H) / (2 tan(angle/2)); pixel
    (i, j) looks along D + x R + y U, x = (i+0.5)/W - 0.5, y = 0.5 - (j+0.5)/H."""
    fwd = (look - loc) / np.linalg.norm(look - loc)
    right = np.cross([0, 1, 0], fwd)
    right /= np.linalg.norm(right)
    up = np.cross(fwd, right)
    aspect = W / H
    d = fwd * aspect / (2 * math.tan(math.radians(angle) / 2))
    x = (np.arange(W) + 0.5) / W - 0.5
    y = 0.5 - (np.arange(H) + 0.5) / H
    rays = d + x[None, :, None] * right * aspect + y[:, None, None] * up
    return rays / np.linalg.norm(rays, axis=-1, keepdims=True), fwd


def rotate_y(v, degrees):
    """POV-Ray's `rotate y*degrees`: vrotate(z, 90*y) = x."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return np.stack([v[..., 0] * c + v[..., 2] * s, v[..., 1], -v[..., 0] * s + v[..., 2] * c], axis=-1)


def analytic_truth(turn=0.0, shift=np.zeros(3)):
    """Planar depth per pixel (inf = sky): first hit of floor, wall and sphere, for the
    camera above, optionally followed by `rotate y*turn translate shift`."""
    rays, fwd = look_at_rays(LOC, LOOK, ANGLE)
    rays, fwd, loc = rotate_y(rays, turn), rotate_y(fwd, turn), rotate_y(LOC, turn) + shift
    z = np.full((H, W), np.inf)
    for j in range(H):
        for i in range(W):
            ray = rays[j, i]
            hits = []
            if ray[1] < 0:
                hits.append(-loc[1] / ray[1])
            if ray[2] > 0:
                t = (6 - loc[2]) / ray[2]
                p = loc + t * ray
                if abs(p[0]) <= 3 and 0 <= p[1] <= 2.5:
                    hits.append(t)
            oc = loc - SPHERE_C
            b, c = oc @ ray, oc @ oc - SPHERE_R ** 2
            if b * b - c >= 0 and -b - math.sqrt(b * b - c) > 0:
                hits.append(-b - math.sqrt(b * b - c))
            if hits:
                z[j, i] = min(hits) * (ray @ fwd)
    return z


class RenderPov(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="test_render_pov.")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def check_depth(self, z, truth=None):
        truth = analytic_truth() if truth is None else truth
        sky = np.isinf(truth)
        self.assertTrue(np.all(z[sky] >= 1e9), "sky pixels must read as sky")
        self.assertTrue(np.all(z[~sky] < 1e9), "surfaces must not read as sky")
        rel = np.abs(z[~sky] / truth[~sky] - 1)
        near = truth[~sky] < 100  # the floor near the horizon runs to any depth
        print(f"analytic scene: planar depth median error {np.median(rel):.2e}, 99th percentile "
              f"{np.percentile(rel[near], 99):.2e} over {int(near.sum())} pixels nearer than 100")
        self.assertLessEqual(np.median(rel), 0.005)
        self.assertLessEqual(np.percentile(rel[near], 99), 0.02)

    def test_analytic_scene_depth_and_fov(self):
        scene, out = self.write("analytic.pov", ANALYTIC), os.path.join(self.dir, "analytic.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 0, log)
        spec, px = read(out)
        self.assertEqual(list(spec.channelnames), ["R", "G", "B", "Z"])
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3])

    def test_scene_units_far_from_the_first_fog_distance(self):
        # The same scene in units 100 times larger and 100 times smaller: the fog ladder must
        # find it from its first distance (10 units) either way.
        for scale in (100.0, 0.01):
            loc, look = LOC * scale, LOOK * scale
            camera = ANALYTIC[ANALYTIC.index("camera"):ANALYTIC.index("light_source")]
            scaled = camera.replace(f"<{LOC[0]}, {LOC[1]}, {LOC[2]}>", f"<{loc[0]}, {loc[1]}, {loc[2]}>").replace(
                f"<{LOOK[0]}, {LOOK[1]}, {LOOK[2]}>", f"<{look[0]}, {look[1]}, {look[2]}>")
            objects = ANALYTIC[ANALYTIC.index("plane"):]
            scene = self.write("scaled.pov", ANALYTIC[:ANALYTIC.index("camera")] + scaled
                               + f"light_source {{ <-3, 8, -6>*{scale} rgb 1 }}\n"
                               + f"union {{ {objects} scale {scale} }}\n")
            out = os.path.join(self.dir, "scaled.exr")
            rc, log = render(scene, out, "--width", str(W), "--height", str(H))
            self.assertEqual(rc, 0, log)
            z = read(out)[1][..., 3]
            self.check_depth(np.where(z >= 1e9, z, z / scale))

    def test_far_wall_beyond_a_depth_gap(self):
        # A wall 3000 units away behind the scene (depths ~5-30): the ladder must not take the
        # empty range between for sky, and the wall must not read as sky.
        scene = self.write("gap.pov", ANALYTIC + "box { <-1e4, 0, 3000>, <1e4, 400, 3001> pigment { rgb 0.5 } }\n")
        out = os.path.join(self.dir, "gap.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 0, log)
        rays, fwd = look_at_rays(LOC, LOOK, ANGLE)
        t = (3000 - LOC[2]) / rays[..., 2]
        wall = np.where((t > 0) & (LOC[1] + t * rays[..., 1] <= 400), t * (rays @ fwd), np.inf)
        truth = analytic_truth()
        truth = np.where(np.isinf(truth), wall, truth)
        self.assertGreater(int((np.isinf(analytic_truth()) & ~np.isinf(wall)).sum()), 50)
        self.check_depth(read(out)[1][..., 3], truth)

    def test_camera_in_an_include_needs_fov(self):
        lines = ANALYTIC.splitlines()
        cam = [k for k, l in enumerate(lines) if l.startswith("camera")][0]
        self.write("cam.inc", "\n".join(lines[cam:cam + 2]) + "\n")
        scene = self.write("included.pov", "\n".join(lines[:cam] + ['#include "cam.inc"'] + lines[cam + 2:]))
        out = os.path.join(self.dir, "included.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertNotEqual(rc, 0)
        self.assertIn("--fov", log)
        self.assertFalse(os.path.exists(out))
        rc, log = render(scene, out, "--width", str(W), "--height", str(H), "--fov", f"{ANGLE}deg")
        self.assertEqual(rc, 0, log)
        spec, px = read(out)
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3])

    def test_declared_transformed_and_branch_cameras(self):
        lines = ANALYTIC.splitlines()
        cam = [k for k, l in enumerate(lines) if l.startswith("camera")][0]
        camera = " ".join(lines[cam:cam + 2])[:-1] + " rotate y*12 translate <0.3, 0.1, -0.2> }"
        scene = self.write("declared.pov", "\n".join(lines[:cam] + [f"#declare Cam = {camera}", "camera { Cam }"]
                                                     + lines[cam + 2:]))
        out = os.path.join(self.dir, "declared.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 0, log)
        spec, px = read(out)
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3], analytic_truth(12.0, np.array([0.3, 0.1, -0.2])))
        # Two cameras in #if branches (as Debian's landscape.pov): the text's last one is not
        # the one rendered; the render check picks the other.
        other = "camera { location <2, 3, -6> right x*image_width/image_height angle 35 look_at <0, 1, 0> }"
        scene = self.write("branches.pov", "\n".join(lines[:cam] + ["#declare View = 1;", "#if (View = 1)"]
                                                     + lines[cam:cam + 2] + ["#else", other, "#end"]
                                                     + lines[cam + 2:]))
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 0, log)
        spec, px = read(out)
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3])

    def test_camera_misread_is_caught(self):
        # A macro's camera: the probe evaluates the block after the scene, where A is the global
        # 30, while POV-Ray rendered Cam(55). The test plane sees the difference.
        lines = ANALYTIC.splitlines()
        cam = [k for k, l in enumerate(lines) if l.startswith("camera")][0]
        camera = " ".join(lines[cam:cam + 2]).replace(f"angle {ANGLE}", "angle A")
        scene = self.write("macro.pov", "\n".join(lines[:cam] + ["#declare A = 30;", f"#macro Cam(A) {camera} #end",
                                                                 f"Cam({ANGLE})"] + lines[cam + 2:]))
        out = os.path.join(self.dir, "macro.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 1, log)
        self.assertIn("does not match the one POV-Ray renders with", log)
        self.assertFalse(os.path.exists(out))
        rc, log = render(scene, out, "--width", str(W), "--height", str(H), "--fov", str(ANGLE))
        self.assertEqual(rc, 0, log)
        spec, px = read(out)
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3])

    def test_shipped_scenes_radiance_and_fov(self):
        self.assertTrue(os.path.isdir(EXAMPLES), f"{EXAMPLES}: missing (packaging/install-deps.sh installs "
                        "povray-examples; a dpkg path-exclude of /usr/share/doc would drop it)")
        for name, angle in (("pawns", 40.0), ("woodbox", 45.0)):
            scene = os.path.join(EXAMPLES, name + ".pov")
            out = os.path.join(self.dir, name + ".exr")
            rc, log = render(scene, out, "--width", str(W), "--height", str(H))
            self.assertEqual(rc, 0, log)
            spec, px = read(out)
            self.assertAlmostEqual(spec.getattribute("wavecam.fov"), angle, places=4, msg=name)
            # POV-Ray's own render of the unmodified scene, with the same options.
            plain = os.path.join(self.dir, name + "_plain.exr")
            subprocess.run(["povray", "-D", "-V", f"+I{scene}", "+FE", f"+O{plain}", f"+W{W}", f"+H{H}",
                            "+A0.3", "-J"], cwd=EXAMPLES, check=True, capture_output=True)
            _, ref = read(plain)
            np.testing.assert_array_equal(px[..., :3], ref[..., :3], err_msg=name)
            self.assertGreater(np.abs(px[:, ::-1, :3] - ref[..., :3]).mean(), 0.01, f"{name} is symmetric")
            z = px[..., 3]
            self.assertTrue(np.all(np.isfinite(z)) and np.all(z > 0), name)
            if name == "woodbox":
                # Its floor is `plane { y, 0 }` and its camera `location <-5, 10, -15> angle 45
                # right x*image_width/image_height look_at <0,0,0>`; the image's four corners
                # (6 x 6 pixels each) see only floor: planar depth there is analytic.
                rays, fwd = look_at_rays(np.array([-5.0, 10, -15]), np.zeros(3), 45.0)
                truth = (-10.0 / rays[..., 1]) * (rays @ fwd)
                corners = np.zeros((H, W), bool)
                corners[:6, :6] = corners[:6, -6:] = corners[-6:, :6] = corners[-6:, -6:] = True
                rel = np.abs(z[corners] / truth[corners] - 1)
                print(f"woodbox floor corners: planar depth median error {np.median(rel):.2e}, worst {rel.max():.2e}")
                self.assertLessEqual(np.median(rel), 0.005)

    def refused(self, scene, expected, *extra):
        out = os.path.join(self.dir, "refused.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H), *extra)
        self.assertEqual(rc, 1, log)
        self.assertIn(expected, log)
        self.assertEqual([f for f in os.listdir(self.dir) if not f.endswith((".pov", ".inc"))], [],
                         f"files left behind: {log}")

    def test_refusals(self):
        body = ANALYTIC.split("light_source", 1)[1]
        self.refused(self.write("nocamera.pov", "#version 3.7;\nlight_source" + body), "no camera")
        self.refused(self.write("fog.pov", ANALYTIC + "fog { distance 30 color rgb 0.7 }\n"), "its own 'fog'")
        self.refused(self.write("media.pov", ANALYTIC + "sphere { 0, 2 hollow pigment { rgbt 1 } interior {"
                                " media { scattering { 1, 0.2 } } } }\n"), "its own 'media'")
        self.refused(self.write("broken.pov", ANALYTIC + "sphere { <0, 1, 0> 0.5 pigment { rgb 1 }\n"),
                     "Parse Error")
        self.refused(self.write("ortho.pov", ANALYTIC.replace("camera {", "camera { orthographic")),
                     "'orthographic'")
        self.refused(self.write("fovclash.pov", ANALYTIC), "disagrees with the scene's camera", "--fov", "30deg")
        self.refused(self.write("stretched.pov", ANALYTIC.replace("right x*image_width/image_height", "right x")),
                     "pixels are not square")
        self.refused(os.path.join(EXAMPLES, "chess2.pov"), "focal blur")
        # plane { z, 10 } is solid for z < 10, around the camera: the fog cannot reach the surfaces.
        self.refused(self.write("inside.pov", ANALYTIC + "plane { z, 10 pigment { rgb 1 } }\n"),
                     "camera inside a non-hollow object")


if __name__ == "__main__":
    unittest.main(verbosity=2)
