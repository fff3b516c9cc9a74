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
# wavecam itself, for the tests that diffract what the harness wrote (ctest sets them)
WAVECAM = os.environ.get("WAVECAM_BINARY")
PLUGIN_DIR = os.environ.get("WAVECAM_PLUGIN_DIR")


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


    # --- scenes as POV-Ray users keep them -------------------------------------------

    def test_folders_with_spaces_and_a_local_camera(self):
        # The scene in a folder with spaces, its camera from top-level #local values, a relative
        # #include beside it, a macro's own #local left alone; the output in a folder with spaces.
        folder = os.path.join(self.dir, "my scenes")
        os.mkdir(folder)
        os.mkdir(os.path.join(self.dir, "out dir"))
        lines = ANALYTIC.splitlines()
        cam = [k for k, l in enumerate(lines) if l.startswith("camera")][0]
        with open(os.path.join(folder, "view values.inc"), "w") as f:
            f.write(f"#declare Look = <{LOOK[0]}, {LOOK[1]}, {LOOK[2]}>;\n")
        local = ["#include \"view values.inc\"",
                 f"#local Angle = {ANGLE};", f"#local Where = <{LOC[0]}, {LOC[1]}, {LOC[2]}>;",
                 "#macro Unused() #local Angle = 10; #end",
                 "camera { location Where right x*image_width/image_height angle Angle", "  look_at Look }"]
        scene = os.path.join(folder, "local camera.pov")
        with open(scene, "w") as f:
            f.write("\n".join(lines[:cam] + local + lines[cam + 2:]) + "\n")
        out = os.path.join(self.dir, "out dir", "local camera.exr")
        rc, log = render(scene, out, "--width", str(W), "--height", str(H))
        self.assertEqual(rc, 0, log)
        self.assertIn("camera checked", log)
        spec, px = read(out)
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        self.check_depth(px[..., 3])

    def test_photon_settings_are_not_participating_media(self):
        # photons { media ... } in global_settings sets up photon mapping; only a media block (an
        # object's interior, the atmosphere) is participating media, and its line is named.
        photons = ANALYTIC + "global_settings { photons { spacing 0.5 media on } }\n"
        scene, out = self.write("photons.pov", photons), os.path.join(self.dir, "photons.exr")
        rc, log = render(scene, out, "--width", "32", "--height", "24")
        self.assertEqual(rc, 0, log)
        self.assertAlmostEqual(read(out)[0].getattribute("wavecam.fov"), ANGLE, places=4)
        os.remove(out)
        media = photons + "sphere { 0, 2 hollow pigment { rgbt 1 }\n  interior { media { scattering { 1, 0.2 } } } }\n"
        line = media.splitlines().index("  interior { media { scattering { 1, 0.2 } } } }") + 1
        self.refused(self.write("media2.pov", media), f"media2.pov:{line}: the scene has its own 'media'")

    def test_clock_animation_writes_numbered_frames(self):
        # --frames 1-3 with the clock from 0 to 2 (+KI0 +KF2): the sphere moves; three EXRs named
        # as wavecam apply --frames reads them, each with its clock.
        scene = self.write("anim.pov", ANALYTIC + "sphere { <-1.5 + 1.5*clock, 0.5, 0>, 0.5 pigment { rgb 1 } }\n")
        rc, log = render(scene, os.path.join(self.dir, "anim.#.exr"), "--width", "32", "--height", "24",
                         "--frames", "1-3", "+KI0", "+KF2")
        self.assertEqual(rc, 0, log)
        frames = [read(os.path.join(self.dir, f"anim.000{f}.exr")) for f in (1, 2, 3)]
        for f, (spec, _) in enumerate(frames):
            self.assertEqual(spec.getattribute("wavecam.pov-frame"), f + 1)
            self.assertAlmostEqual(spec.getattribute("wavecam.pov-clock"), float(f), places=5)
            self.assertAlmostEqual(spec.getattribute("wavecam.fov"), ANGLE, places=4)
        for a, b in ((0, 1), (1, 2), (0, 2)):
            self.assertGreater(np.abs(frames[a][1][..., :3] - frames[b][1][..., :3]).mean(), 1e-3, (a, b))
            self.assertGreater(np.abs(frames[a][1][..., 3] - frames[b][1][..., 3]).max(), 0.1, (a, b))
        # the %04d spelling names the same files; no pattern with --frames is refused first
        rc, log = render(scene, os.path.join(self.dir, "pct.%04d.exr"), "--width", "32", "--height", "24",
                         "--frames", "2", "+KI0", "+KF2")
        self.assertEqual(rc, 0, log)
        self.assertTrue(os.path.exists(os.path.join(self.dir, "pct.0002.exr")))
        rc, log = render(scene, os.path.join(self.dir, "flat.exr"), "--frames", "1-3")
        self.assertEqual((rc, "POV-Ray run" in log), (1, False), log)
        self.assertIn("frame number pattern", log)
        if WAVECAM:
            proc = subprocess.run([WAVECAM, "apply", os.path.join(self.dir, "anim.#.exr"), "-o",
                                   os.path.join(self.dir, "d.#.exr"), "--frames", "1-3", "--film-distance", "20mm",
                                   "--wavelengths", "3"], capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
            for f in (1, 2, 3):
                self.assertTrue(os.path.exists(os.path.join(self.dir, f"d.000{f}.exr")))

    def scaled_scene(self, name, scale):
        """ANALYTIC in units `scale` times smaller (0.01: the same scene in centimetres), shrunk
        20 times so that its depths (0.2 m to 1.5 m) shape the PSF."""
        size = 0.05 / scale
        loc, look = LOC * size, LOOK * size
        camera = ANALYTIC[ANALYTIC.index("camera"):ANALYTIC.index("light_source")]
        camera = camera.replace(f"<{LOC[0]}, {LOC[1]}, {LOC[2]}>", f"<{loc[0]!r}, {loc[1]!r}, {loc[2]!r}>").replace(
            f"<{LOOK[0]}, {LOOK[1]}, {LOOK[2]}>", f"<{look[0]!r}, {look[1]!r}, {look[2]!r}>")
        objects = ANALYTIC[ANALYTIC.index("plane"):]
        return self.write(name, ANALYTIC[:ANALYTIC.index("camera")] + camera
                          + f"light_source {{ <-3, 8, -6>*{size!r} rgb 1 }}\n" + f"union {{ {objects} scale {size!r} }}\n")

    def test_depth_scale_gives_metres(self):
        metres, cm = self.scaled_scene("metres.pov", 1.0), self.scaled_scene("centimetres.pov", 0.01)
        size = ["--width", "32", "--height", "24"]
        outs = {k: os.path.join(self.dir, k + ".exr") for k in ("m", "cm", "cm_units")}
        for scene, out, extra in ((metres, outs["m"], []), (cm, outs["cm"], ["--depth-scale", "1cm"]),
                                  (cm, outs["cm_units"], [])):
            rc, log = render(scene, out, *size, *extra)
            self.assertEqual(rc, 0, log)
        (spec_m, m), (spec_cm, c), (_, units) = (read(outs[k]) for k in ("m", "cm", "cm_units"))
        self.assertEqual(spec_cm.getattribute("wavecam.scene-unit"), "0.01m")
        self.assertIsNone(spec_m.getattribute("wavecam.scene-unit"))
        sky = m[..., 3] >= 1e9
        np.testing.assert_array_equal(sky, c[..., 3] >= 1e9)
        self.assertGreater(int((~sky).sum()), 300)
        rel = np.abs(c[..., 3][~sky] / m[..., 3][~sky] - 1)
        print(f"depth-scale 1cm against the scene in metres: planar depth median {np.median(rel):.1e}, "
              f"worst {rel.max():.1e}; depths {m[..., 3][~sky].min():.3f} to {m[..., 3][~sky].max():.3f} m")
        self.assertLessEqual(np.median(rel), 2e-3)
        self.assertLessEqual(rel.max(), 1e-2)
        np.testing.assert_allclose(units[..., 3][~sky] / 100, m[..., 3][~sky], rtol=1e-2)  # cm without the scale
        np.testing.assert_allclose(c[..., :3], m[..., :3], atol=2e-3)
        if not WAVECAM:
            return
        # wavecam: the same blur from the metres file, the converted one, and the cm-units file
        # with wavecam's own depth-scale (command and plugin); the cm file read as metres differs.
        opts = ["--film-distance", "20mm", "--pinhole", "0.2mm", "--wavelengths", "3", "--fov", f"{ANGLE}deg"]

        def apply(src, dst, *extra):
            proc = subprocess.run([WAVECAM, "apply", outs[src], "-o", os.path.join(self.dir, dst), *opts, *extra],
                                  capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
            return read(os.path.join(self.dir, dst))

        a_m, a_cm = apply("m", "a_m.exr")[1], apply("cm", "a_cm.exr")[1]
        spec_units, a_units = apply("cm_units", "a_units.exr", "--depth-scale", "1cm")
        a_wrong = apply("cm_units", "a_wrong.exr")[1]
        self.assertEqual(spec_units.getattribute("wavecam.depth-scale"), "0.01m")
        diff = lambda a, b: float(np.abs(a[..., :3] - b[..., :3]).mean() / np.abs(b[..., :3]).mean())
        print(f"wavecam apply: metres vs --depth-scale 1cm (harness) {diff(a_cm, a_m):.1e}, vs wavecam "
              f"--depth-scale 1cm {diff(a_units, a_m):.1e}, cm read as metres {diff(a_wrong, a_m):.1e} (relative mean)")
        self.assertLess(diff(a_cm, a_m), 3e-3)
        self.assertLess(diff(a_units, a_m), 3e-3)
        # (measured: 5.7e-7 and 5.5e-7 against 2.8e-4)
        self.assertGreater(diff(a_wrong, a_m), 1e-4)
        self.assertGreater(diff(a_wrong, a_m), 20 * max(diff(a_cm, a_m), diff(a_units, a_m)))
        if PLUGIN_DIR:
            hinted = os.path.join(self.dir, "a_plugin.exr")
            name = outs["cm_units"] + ".wavecam?depth-scale=1cm&film-distance=20mm&pinhole=0.2mm&wavelengths=3"
            proc = subprocess.run(["oiiotool", name, "-o", hinted], capture_output=True, text=True,
                                  env={**os.environ, "OIIO_LIBRARY_PATH": PLUGIN_DIR})
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
            spec_p, a_plugin = read(hinted)
            self.assertEqual(spec_p.getattribute("wavecam.depth-scale"), "0.01m")
            self.assertLess(diff(a_plugin, a_units), 1e-4)

    def test_depth_scale_on_a_scaled_depth_is_refused(self):
        # A harness output in metres (--depth-scale 1cm: wavecam.scene-unit) given a depth scale
        # again is refused by the command and the plugin, naming the attribute; nothing written.
        out = os.path.join(self.dir, "cm.exr")
        rc, log = render(self.scaled_scene("cm.pov", 0.01), out, "--width", "32", "--height", "24", "--depth-scale", "1cm")
        self.assertEqual(rc, 0, log)
        if not WAVECAM:
            return
        opts = ["--film-distance", "20mm", "--pinhole", "0.2mm", "--wavelengths", "3"]
        result = os.path.join(self.dir, "twice.exr")
        proc = subprocess.run([WAVECAM, "apply", out, "-o", result, *opts, "--depth-scale", "1cm"],
                              capture_output=True, text=True)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("wavecam.scene-unit 0.01m", proc.stderr)
        self.assertIn("--depth-scale", proc.stderr)
        self.assertFalse(os.path.exists(result))
        proc = subprocess.run([WAVECAM, "apply", out, "-o", result, *opts], capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        # the output's depth is the input's: it keeps the unit, so it is refused again read back
        self.assertEqual(read(result)[0].getattribute("wavecam.scene-unit"), "0.01m")
        if PLUGIN_DIR:
            proc = subprocess.run(["oiiotool", out + ".wavecam?depth-scale=1cm&film-distance=20mm", "-o",
                                   os.path.join(self.dir, "p.exr")], capture_output=True, text=True,
                                  env={**os.environ, "OIIO_LIBRARY_PATH": PLUGIN_DIR})
            self.assertNotEqual(proc.returncode, 0)
            self.assertIn("wavecam.scene-unit", proc.stdout + proc.stderr)

    def test_ini_animation_keeps_povrays_frame_clock(self):
        # An .ini animation of 51 frames (clock 0 to 1): --frames 2-3 renders the ini's frames 2
        # and 3, clock 0.02 and 0.04, the very images `povray anim.ini +SF2 +EF3` renders; +SF2
        # +EF3 in place of --frames give the same; a frame beyond the ini's is refused.
        self.write("anim.pov", ANALYTIC + "sphere { <-1.5 + 60*clock, 0.5, 0>, 0.5 pigment { rgb 1 } }\n")
        ini = self.write("anim.ini", "Input_File_Name=anim.pov\nInitial_Frame=1\nFinal_Frame=51\n"
                         "Initial_Clock=0\nFinal_Clock=1\nWidth=32\nHeight=24\n")
        rc, log = render(ini, os.path.join(self.dir, "h.#.exr"), "--frames", "2-3")
        self.assertEqual(rc, 0, log)
        rc, log = render(ini, os.path.join(self.dir, "s.#.exr"), "+SF2", "+EF3")
        self.assertEqual(rc, 0, log)
        own = os.path.join(self.dir, "own")
        os.mkdir(own)
        proc = subprocess.run(["povray", "+A0.3", "-J", ini, "+SF2", "+EF3", "-D", "-P", "-V", "+FE",
                               "+O" + os.path.join(own, "own.exr")], cwd=self.dir, capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr[-2000:])
        for frame, clock in ((2, 0.02), (3, 0.04)):
            spec, harness = read(os.path.join(self.dir, f"h.000{frame}.exr"))
            self.assertEqual(spec.getattribute("wavecam.pov-frame"), frame)
            self.assertAlmostEqual(spec.getattribute("wavecam.pov-clock"), clock, places=6)
            _, povray = read(os.path.join(own, f"own{frame:02d}.exr"))
            np.testing.assert_array_equal(harness[..., :3], povray[..., :3])
            np.testing.assert_array_equal(read(os.path.join(self.dir, f"s.000{frame}.exr"))[1], harness)
        self.assertGreater(np.abs(read(os.path.join(self.dir, "h.0002.exr"))[1][..., :3]
                                  - read(os.path.join(self.dir, "h.0003.exr"))[1][..., :3]).max(), 0.1)
        rc, log = render(ini, os.path.join(self.dir, "x.#.exr"), "--frames", "50-52")
        self.assertEqual(rc, 1, log)
        self.assertIn("beyond the animation's frames 1-51", log)
        self.assertNotIn("POV-Ray run", log)
        rc, log = render(ini, os.path.join(self.dir, "x.#.exr"), "--frames", "2", "+SF3")
        self.assertEqual(rc, 1, log)
        self.assertIn("given twice", log)

    def test_fog_in_a_library_include_is_named(self):
        # fog in an include found only through a +L library folder (and one more level of
        # #include there): refused before any POV-Ray run, naming the file, its line and 'fog'.
        lib = os.path.join(self.dir, "lib")
        os.mkdir(lib)
        with open(os.path.join(lib, "look.inc"), "w") as f:
            f.write('#include "weather"\n')
        with open(os.path.join(lib, "weather.inc"), "w") as f:
            f.write("// the mood\n#declare Thick = 30;\nfog { distance Thick color rgb 0.7 }\n")
        scene = self.write("lib.pov", '#include "look.inc"\n' + ANALYTIC)
        rc, log = render(scene, os.path.join(self.dir, "lib.exr"), "--width", "32", "--height", "24", "+L" + lib)
        self.assertEqual(rc, 1, log)
        self.assertIn(os.path.join(os.path.realpath(lib), "weather.inc") + ":3", log)
        self.assertIn("its own 'fog'", log)
        self.assertNotIn("POV-Ray run", log)
        # the same folder named by an ini's Library_Path
        ini = self.write("lib.ini", f"Library_Path={lib}\n")
        rc, log = render(scene, os.path.join(self.dir, "lib.exr"), "--width", "32", "--height", "24", ini)
        self.assertEqual(rc, 1, log)
        self.assertIn("its own 'fog'", log)

    def test_names_options_and_ini_files(self):
        size = ["--width", "32", "--height", "24"]
        # the output's extension first: nothing runs
        rc, log = render(self.write("any.pov", ANALYTIC), os.path.join(self.dir, "out.png"), *size)
        self.assertEqual(rc, 1, log)
        self.assertIn("out.png: the harness writes OpenEXR only", log)
        self.assertNotIn("POV-Ray run", log)
        rc, log = render(os.path.join(self.dir, "missing.pov"), os.path.join(self.dir, "out.PNG"))
        self.assertIn("OpenEXR only", log)
        # SCENE.POV (any case) and OUT.EXR
        rc, log = render(self.write("SCENE.POV", ANALYTIC), os.path.join(self.dir, "UPPER.EXR"), *size)
        self.assertEqual(rc, 0, log)
        self.assertAlmostEqual(read(os.path.join(self.dir, "UPPER.EXR"))[0].getattribute("wavecam.fov"), ANGLE, places=4)
        # An ini as SCENE (Input_File_Name, its size, a Declare) and options after OUT: Declare=,
        # a user ini, +Q; the Declare'd angle reaches the camera.
        declared = ANALYTIC.replace(f"angle {ANGLE}", "angle Lens")
        self.write("declared.pov", declared)
        ini = self.write("render.ini", "; a user's ini, as kept for POV-Ray itself\nInput_File_Name=declared.pov\n"
                         "Output_File_Type=N\nOutput_File_Name=declared.png\nDisplay=On\nPause_When_Done=On\n"
                         "Output_Alpha=On\nWidth=40\nHeight=30\nDeclare=Lens=40\n")
        out = os.path.join(self.dir, "from ini.exr")
        rc, log = render(ini, out)
        self.assertEqual(rc, 0, log)
        spec, _ = read(out)
        self.assertEqual((spec.width, spec.height), (40, 30))
        self.assertAlmostEqual(spec.getattribute("wavecam.fov"), 40.0, places=4)
        self.assertEqual(spec.getattribute("wavecam.scene"), "declared.pov")
        extra = self.write("quality.ini", "Quality=4\n")
        rc, log = render(self.write("declared2.pov", declared), out, *size, "Declare=Lens=35", extra, "+Q5")
        self.assertEqual(rc, 0, log)
        self.assertAlmostEqual(read(out)[0].getattribute("wavecam.fov"), 35.0, places=4)
        self.assertFalse([f for f in os.listdir(self.dir) if f.endswith(".pov.pov")])
        # options the harness sets itself are refused before any run
        self.assertFalse(os.path.exists(os.path.join(self.dir, "declared.png")))
        for option, expected in (("+O/tmp/x.exr", "set by the harness itself"), ("+KFF3", "give --frames"),
                                 ("+Iother.pov", "set by the harness itself"), ("Start_Row=0.5", "part of the image"),
                                 (self.write("anim.ini", "Initial_Frame=1\nFinal_Frame=5\n"), "give --frames"),
                                 ("Output_File_Type=N", "set by the harness itself"), ("scene2.pov", "not a POV-Ray option")):
            rc, log = render(self.write("opt.pov", ANALYTIC), out, *size, option)
            self.assertEqual(rc, 1, log)
            self.assertIn(expected, log)
            self.assertNotIn("POV-Ray run", log)

    def test_refused_after_the_first_parse(self):
        # What the first POV-Ray run (a parse) tells is refused then, before the radiance render:
        # non-square pixels, a camera that cannot be read without --fov; a --fov against the
        # camera names both values.
        size = ["--width", "32", "--height", "24"]
        rc, log = render(self.write("stretched.pov", ANALYTIC.replace("right x*image_width/image_height", "right x")),
                         os.path.join(self.dir, "s.exr"), *size)
        self.assertEqual(rc, 1, log)
        self.assertIn("pixels are not square", log)
        self.assertNotIn("radiance render", log)
        lines = ANALYTIC.splitlines()
        cam = [k for k, l in enumerate(lines) if l.startswith("camera")][0]
        self.write("cam.inc", "\n".join(lines[cam:cam + 2]) + "\n")
        rc, log = render(self.write("included.pov", "\n".join(lines[:cam] + ['#include "cam.inc"'] + lines[cam + 2:])),
                         os.path.join(self.dir, "s.exr"), *size)
        self.assertEqual(rc, 1, log)
        self.assertIn("pass --fov", log)
        self.assertNotIn("radiance render", log)
        self.refused(self.write("fov.pov", ANALYTIC), f"--fov 50 deg disagrees with the scene's camera, whose "
                     f"horizontal field of view is {ANGLE:.4f} deg", "--fov", "50deg")


if __name__ == "__main__":
    unittest.main(verbosity=2)
