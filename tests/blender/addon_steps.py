# Steps of the Blender add-on test, run inside Debian's Blender by blender_addon_test.sh:
#   blender -b --python addon_steps.py -- install ZIP WAVECAM
#   blender -b --python addon_steps.py -- scene OUT.blend RENDER_PREFIX (landscape | portrait)
#   blender -b SCENE.blend --python addon_steps.py -- check FRAME...
#   blender -b SCENE.blend --python addon_steps.py -- errors   (stills, and every refusal)
#   blender -b SCENE.blend --python addon_steps.py -- settings (units, vignetting, ranges)
#   blender -b --python addon_steps.py -- oldfile OUT.blend    (saved as the add-on once did)
#   blender -b OUT.blend --python addon_steps.py -- loadold
# The truth for the field of view is written here from the lens and sensor, independently of
# the add-on: a sensor fit of Auto spans the sensor width across the frame's longer side.
import math
import os
import re
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
step = args[0]
failures = []


def expect(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message, flush=True)


def install(zip_path, wavecam):
    bpy.ops.preferences.addon_install(filepath=zip_path)
    bpy.ops.preferences.addon_enable(module="wavecam_blender")
    bpy.context.preferences.addons["wavecam_blender"].preferences.wavecam_path = wavecam
    bpy.ops.wm.save_userpref()


def make_scene(blend, prefix, shape):
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 2
    scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
    scene.cycles.device = 'CPU'
    scene.render.resolution_x, scene.render.resolution_y = (48, 32) if shape == "landscape" else (32, 48)
    scene.render.resolution_percentage = 100
    scene.render.filepath = prefix
    scene.frame_start, scene.frame_end = 1, 2
    cam = scene.camera.data
    cam.sensor_fit = 'AUTO'
    cam.sensor_width = 36
    # the lens changes between the two frames: frame 2's fov must follow it
    cam.lens = 35
    cam.keyframe_insert("lens", frame=1)
    cam.lens = 60
    cam.keyframe_insert("lens", frame=2)
    from wavecam_blender import reports
    said = []
    report_info = reports.info
    reports.info = lambda message: (said.append(message), report_info(message))
    scene.render.image_settings.file_format = 'PNG'
    cam.wavecam.enabled = True  # turns on the Z pass and OpenEXR MultiLayer, and says so
    cam.wavecam.enabled = False
    cam.wavecam.enabled = True  # nothing left to change: nothing said
    reports.info = report_info
    cam.wavecam.wavelength_count = 3
    expect(scene.view_layers[0].use_pass_z, "enabling wavecam turned on the Z pass")
    expect(scene.render.image_settings.file_format == 'OPEN_EXR_MULTILAYER', "enabling wavecam chose EXR multilayer")
    expect(len(said) == 1 and "File Format PNG changed to OpenEXR MultiLayer" in said[0] and "Z pass" in said[0],
           f"enabling wavecam said once what it changed: {said}")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    # the same frame with sensor fit Vertical (the sensor height spans the frame's height)
    cam.sensor_fit = 'VERTICAL'
    cam.sensor_height = 24
    scene.render.filepath = prefix + "vertical_"
    bpy.ops.wm.save_as_mainfile(filepath=blend[:-len(".blend")] + "_vertical.blend")


def true_fov(scene, frame):
    scene.frame_set(frame)
    cam = scene.camera.data
    w, h = scene.render.resolution_x, scene.render.resolution_y
    if cam.sensor_fit == 'VERTICAL':  # tangent of the half angle across the height, scaled to the width
        half_width = cam.sensor_height / 2 / cam.lens * w / h
    else:  # the sensor width across the width (Horizontal), or across the longer side (Auto)
        half_width = cam.sensor_width / 2 / cam.lens
        if cam.sensor_fit == 'AUTO' and h > w:
            half_width *= w / h
    return math.degrees(2 * math.atan(half_width)), cam.lens


def blender_reads(path):
    """The layer and passes Blender finds in an EXR (a compositor Image node's outputs)."""
    scene = bpy.context.scene
    scene.use_nodes = True
    node = scene.node_tree.nodes.new("CompositorNodeImage")
    node.image = bpy.data.images.load(path, check_existing=False)
    found = (node.layer, [o.name for o in node.outputs if o.enabled])
    scene.node_tree.nodes.remove(node)
    return found


def tagging_is_lossless(frame_path):
    """exr_fov.write_fov on a copy: the same pixels, channels and header, plus wavecam.fov."""
    import shutil
    import OpenImageIO as oiio
    from wavecam_blender import exr_fov
    copy = frame_path[:-4] + ".copy.exr"
    shutil.copyfile(frame_path, copy)
    exr_fov.write_fov(copy, 12.5)
    before, after = oiio.ImageBuf(frame_path), oiio.ImageBuf(copy)
    expect(before.get_pixels().tobytes() == after.get_pixels().tobytes(), "tagging keeps the pixels")
    expect(abs(after.spec().getattribute("wavecam.fov") - 12.5) < 1e-6, "tagging writes wavecam.fov")
    for a in before.spec().extra_attribs:
        if a.name not in ("wavecam.fov", "oiio:subimages"):
            expect(after.spec().getattribute(a.name) == a.value, f"tagging keeps {a.name}")
    expect([f for f in os.listdir(os.path.dirname(copy)) if "tmp" in f] == [], "no temporary left")
    os.remove(copy)


def check(frames):
    import OpenImageIO as oiio
    scene = bpy.context.scene
    for frame in frames:
        truth, lens = true_fov(scene, frame)
        frame_path = scene.render.frame_path(frame=frame)
        out_path = frame_path[:-len(".exr")] + ".wavecam.exr"
        expect(os.path.isfile(out_path), f"frame {frame}: {out_path} exists")
        if frame == frames[0]:
            tagging_is_lossless(frame_path)
        if not os.path.isfile(out_path):
            continue
        blender_spec = oiio.ImageInput.open(frame_path).spec()
        spec = oiio.ImageInput.open(out_path).spec()
        for name, s in (("Blender's frame", blender_spec), ("the diffracted frame", spec)):
            fov = s.getattribute("wavecam.fov")
            expect(fov is not None and abs(fov - truth) < 0.01,
                   f"frame {frame}: {name}'s wavecam.fov {fov} vs the camera's {truth:.4f} deg")
        expect("wavecam.fov" in spec.getattribute("wavecam.fov-from"), f"frame {frame}: fov-from the file's attribute")
        # film at the lens, the pinhole Rayleigh's 1.9 sqrt(f lambda) at 550 nm
        film = float(spec.getattribute("wavecam.film-distance")[:-2])
        pinhole = float(spec.getattribute("wavecam.pinhole")[:-2])
        optimum = 1.9 * math.sqrt(lens * 1e-3 * 550e-9) * 1e3
        expect(abs(film - lens) < 1e-3, f"frame {frame}: film distance {film} mm vs lens {lens} mm")
        expect(abs(pinhole - optimum) < 1e-4, f"frame {frame}: pinhole {pinhole} mm vs optimum {optimum:.5f} mm")
        expect(list(spec.channelnames) == list(blender_spec.channelnames),
               f"frame {frame}: channels {list(spec.channelnames)} vs Blender's {list(blender_spec.channelnames)}")
        expect(blender_reads(out_path) == blender_reads(frame_path),
               f"frame {frame}: Blender reads the diffracted frame as {blender_reads(out_path)}, "
               f"its own as {blender_reads(frame_path)}")
        print(f"frame {frame}: fov {spec.getattribute('wavecam.fov'):.4f} deg (camera {truth:.4f}), "
              f"pinhole {pinhole:.4f} mm, {out_path}", flush=True)


def errors():
    """Bad setups are reported (stderr, 'wavecam: error:'), never raised; no frame is written."""
    scene = bpy.context.scene
    cam = scene.camera.data
    prefs = bpy.context.preferences.addons["wavecam_blender"].preferences
    good = prefs.wavecam_path

    def render(name, diffracted=False):
        scene.render.filepath = os.path.join(os.path.dirname(bpy.data.filepath), name)
        bpy.ops.render.render(write_still=True)  # a still: written as NAME.exr
        out = scene.render.filepath + ".wavecam.exr"
        expect(os.path.exists(out) == diffracted, f"{name}: diffracted frame {'missing' if diffracted else 'written'}")

    render("still", diffracted=True)  # a good still works
    # no path in the preferences: wavecam found on PATH
    prefs.wavecam_path = ""
    os.environ["PATH"] = os.path.dirname(good) + os.pathsep + os.environ.get("PATH", "")
    render("onpath", diffracted=True)
    prefs.wavecam_path = good
    # a still Blender does not write (F12): saved from the Render Result beside the output path
    bpy.ops.render.render()
    unsaved = os.path.join(os.path.dirname(scene.render.filepath), f"{scene.name}_still_{scene.frame_current:04d}.wavecam.exr")
    expect(os.path.isfile(unsaved), f"unsaved still: {unsaved} written")
    if os.path.isfile(unsaved):
        import OpenImageIO as oiio
        fov = oiio.ImageInput.open(unsaved).spec().getattribute("wavecam.fov")
        truth = true_fov(scene, scene.frame_current)[0]
        expect(abs(fov - truth) < 0.01, f"unsaved still: wavecam.fov {fov} vs the camera's {truth:.4f}")

    # a lossy codec: Blender's file is not rewritten, wavecam is given --fov
    scene.render.image_settings.exr_codec = 'DWAA'
    render("lossy", diffracted=True)
    import OpenImageIO as oiio
    lossy = oiio.ImageInput.open(scene.render.filepath + ".wavecam.exr").spec()
    expect(lossy.getattribute("wavecam.fov-from") == "--fov", "lossy: fov-from --fov")
    expect(oiio.ImageInput.open(scene.render.filepath + ".exr").spec().getattribute("wavecam.fov") is None,
           "lossy: Blender's file left alone")
    scene.render.image_settings.exr_codec = 'ZIP'

    cam.shift_x = 0.1
    render("shifted")  # expect: "has shift"
    cam.shift_x = 0
    prefs.wavecam_path = "/nonexistent/wavecam"
    render("nowavecam")  # expect: "wavecam command was not found"
    prefs.wavecam_path = good
    cam.wavecam.use_wavelength_list = True
    cam.wavecam.wavelength_list = "banana"
    render("badsetting")  # expect: "Wavelength list: 'banana' is not a wavelength"
    cam.wavecam.use_wavelength_list = False
    scene.view_layers[0].use_pass_z = False
    render("nodepth")  # expect: "has no Z pass"


def channel(buf, name):
    return buf.get_pixels()[:, :, list(buf.spec().channelnames).index(name)]


def settings():
    """Refusals are made when the render starts, before the frame is rendered, each naming the
    setting; Unit Scale reaches wavecam as the depth scale; the vignetting switch divides out
    cos^4 of the field angle; the wavelength list and the random-phase runs reach wavecam."""
    import OpenImageIO as oiio
    from wavecam_blender import reports
    scene = bpy.context.scene
    cam = scene.camera.data
    w = cam.wavecam
    folder = os.path.dirname(bpy.data.filepath)
    errors, infos, rendered = [], [], []
    report_error, report_info, report_warning = reports.error, reports.info, reports.warning
    reports.error = lambda message: (errors.append(message), report_error(message))
    reports.info = lambda message: (infos.append(message), report_info(message))
    reports.warning = lambda message: (infos.append(message), report_warning(message))
    bpy.app.handlers.render_post.append(lambda *a: rendered.append(len(errors)))

    def render(name, animation=False):
        del errors[:], infos[:], rendered[:]
        scene.render.filepath = os.path.join(folder, name)
        bpy.ops.render.render(animation=animation, write_still=not animation)
        return scene.render.filepath + ("" if animation else ".wavecam.exr")

    def refused(name, expected, before=True):
        out = render(name)
        expect(not os.path.exists(out), f"{name}: refused, yet {out} written")
        said = [e for e in errors if expected in e]
        expect(len(said) == 1, f"{name}: one error saying '{expected}'; got {errors}")
        expect(not before or (rendered and rendered[0] >= 1),
               f"{name}: the refusal came before the frame was rendered ({rendered})")
        print(f"{name}: {said[0] if said else errors}", flush=True)

    # a pinhole between the longest wavelength and the film's width (36 mm at a 35 mm lens), each
    # value kept as typed and refused quoting it
    w.auto_pinhole = False
    w.pinhole = 0
    expect(w.pinhole == 0, f"pinhole 0 kept as typed, not {w.pinhole}")
    refused("pinhole0", "Pinhole 0 mm is smaller than the longest wavelength (700 nm)")
    w.pinhole = 40
    refused("pinhole40", "Pinhole 40 mm is wider than the film (36 mm across at 35 mm")
    w.auto_pinhole = True
    w.auto_film_distance = False
    w.film_distance = -5
    expect(w.film_distance == -5, f"film distance -5 kept as typed, not {w.film_distance}")
    refused("film_negative", "Film distance -5 mm: the film must lie behind the pinhole; expected 0.1 mm or more")
    w.film_distance = 0.05
    refused("film_short", "Film distance 0.05 mm")
    w.film_distance = 50
    w.auto_film_distance = True
    # every field and menu has a tooltip
    bare = [p.identifier for p in w.bl_rna.properties if p.identifier not in {"rna_type", "name"} and not p.description]
    expect(not bare, f"tooltips: fields without one: {bare}")
    print(f"tooltips: {len(w.bl_rna.properties) - 2} fields, none without one", flush=True)
    # the diffracted image: one datablock for every frame, shown as the Render Result is
    from wavecam_blender import reports as shown
    first = os.path.join(folder, "first.wavecam.exr")
    second = os.path.join(folder, "second.wavecam.exr")
    for path in (first, second):
        oiio.ImageBuf(oiio.ImageSpec(4, 4, 3, "float")).write(path)
    a, b = shown._load(first), shown._load(second)
    images = [i for i in bpy.data.images if i.filepath.endswith(".wavecam.exr")]
    expect(a == b and len(images) == 1, f"images: one datablock for two frames, got {[i.name for i in images]}")
    expect(b.use_view_as_render, "images: shown through the scene's view (View as Render)")
    print(f"images: {len(images)} datablock for two frames, '{b.name}', view as render {b.use_view_as_render}",
          flush=True)
    # Blender's own names for the camera's type
    cam.type = 'ORTHO'
    refused("orthographic", "camera 'Camera' is Orthographic; wavecam needs a Perspective camera")
    cam.type = 'PANO'
    refused("panoramic", "camera 'Camera' is Panoramic")
    cam.type = 'PERSP'
    # an animation saved as PNG: refused before its first frame, and every frame named once
    scene.render.image_settings.file_format = 'PNG'
    render(os.path.join("png", "frame_"), animation=True)
    said = [e for e in errors if "the frame is saved as PNG; wavecam needs OpenEXR" in e]
    named = [i for i in infos if "not diffracted" in i]
    expect(len(errors) == 1 and len(said) == 1, f"png: one refusal naming PNG; got {errors}")
    expect(rendered[:1] == [1], f"png: the refusal came before the first frame was rendered ({rendered})")
    expect(len(named) == 1 and "frames 1, 2 left as Blender rendered them" in named[0],
           f"png: frames 1 and 2 named once; got {infos}")
    expect(not any(f.endswith(".wavecam.exr") for f in os.listdir(os.path.join(folder, "png"))),
           "png: no diffracted frame")
    print(f"png: {said[0] if said else errors}; {named[0] if named else infos}", flush=True)
    scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
    w.use_wavelength_list = True
    w.wavelength_list = "450nm,400nm"
    refused("decreasing", "Wavelength list: 400nm follows 450nm; expected an increasing list")
    w.wavelength_list = "50nm"
    refused("xray", "Wavelength list: 50nm is not light")
    w.use_wavelength_list = False
    w.wavelength_count = 0
    expect(w.wavelength_count == 0, f"wavelengths 0 kept as typed, not {w.wavelength_count}")
    refused("wavelengths0", "Wavelengths 0: expected a count from 1 to 1000")
    w.wavelength_count = 3
    w.method, w.auto_runs, w.runs = 'random-phase', False, 0
    refused("runs0", "Runs 0: expected a count from 1 to 100000")
    w.method, w.auto_runs, w.runs = 'convolution', True, 64
    w.use_wavelength_list = True

    # the listed wavelengths reach wavecam
    w.wavelength_list = "500nm, 600nm"
    out = render("listed")
    spec = oiio.ImageInput.open(out).spec() if os.path.exists(out) else None
    expect(spec is not None and spec.getattribute("wavecam.wavelengths") == "500nm,600nm",
           f"listed: wavecam.wavelengths {spec and spec.getattribute('wavecam.wavelengths')}")
    w.use_wavelength_list = False

    # Unit Scale 0.01 (a scene in centimetres): the depth pass is in units of 1 cm
    scene.unit_settings.scale_length = 0.01
    out = render("centimetres")
    spec = oiio.ImageInput.open(out).spec() if os.path.exists(out) else None
    scale = spec.getattribute("wavecam.depth-scale") if spec else None
    expect(scale is not None and scale.endswith("m") and abs(float(scale[:-1]) - 0.01) < 1e-12,
           f"centimetres: wavecam.depth-scale {scale}, expected 0.01m")
    print(f"centimetres: wavecam.depth-scale {scale}", flush=True)
    scene.unit_settings.scale_length = 1.0

    # vignetting off divides out cos^4 of each pixel's field angle: on a uniform background,
    # off / on at a corner pixel is 1 / cos^4 there (tan = the pixel centre's place on the film
    # over the film distance), and 1 near the centre
    w.vignetting = True
    on = oiio.ImageBuf(render("vignetting_on"))
    w.vignetting = False
    off = oiio.ImageBuf(render("vignetting_off"))
    w.vignetting = True
    width, height = scene.render.resolution_x, scene.render.resolution_y
    half_tan = math.tan(math.radians(true_fov(scene, scene.frame_current)[0]) / 2)
    pitch = 2 * half_tan / width  # tan units per pixel
    tan_x, tan_y = (width / 2 - 0.5) * pitch, (height / 2 - 0.5) * pitch
    expected = (1 + tan_x ** 2 + tan_y ** 2) ** 2  # 1 / cos^4
    r_on, r_off = channel(on, "ViewLayer.Combined.R"), channel(off, "ViewLayer.Combined.R")
    for (j, i) in ((0, 0), (0, width - 1), (height - 1, 0), (height - 1, width - 1)):
        ratio = r_off[j, i] / r_on[j, i]
        expect(abs(ratio / expected - 1) < 0.02, f"vignetting: corner ({i}, {j}) off/on {ratio:.4f}, "
               f"expected 1/cos^4 = {expected:.4f}")
    print(f"vignetting: corner off/on {r_off[0, 0] / r_on[0, 0]:.4f}, 1/cos^4 {expected:.4f}", flush=True)

    # random-phase with its runs
    w.method = 'random-phase'
    w.auto_runs = False
    w.runs = 2
    w.wavelength_count = 1
    out = render("random_phase")
    spec = oiio.ImageInput.open(out).spec() if os.path.exists(out) else None
    expect(spec is not None and spec.getattribute("wavecam.runs") == 2, "random-phase: wavecam.runs 2")
    expect(spec is not None and spec.getattribute("wavecam.summation") == "auto", "random-phase: summation auto")
    # the panel's estimate before the render (a description of the frame: its size, fov and the
    # nearest depth its rays meet) against the job's own estimate line, and the depth pass
    from wavecam_blender import frame_handler, job_estimate
    printed = []
    frame_handler.print = lambda *a, **k: printed.append(" ".join(map(str, a)))
    command = job_estimate.estimate_command(scene, scene.camera, bpy.context.evaluated_depsgraph_get())
    panel = job_estimate.estimate_text(command) if command else None
    out = render("estimated")
    del frame_handler.print
    job = [line for line in printed if " terms, about " in line]
    job_terms = float(re.search(r" = ([0-9.e+-]+) terms", job[0]).group(1)) if job else None
    shown = re.search(r"Estimate: about \S+ here \(([0-9.e+-]+) terms", panel or "")
    panel_terms = float(shown.group(1)) if shown else None
    expect(job_terms and panel_terms and abs(panel_terms / job_terms - 1) < 0.25,
           f"estimate: the panel's {panel!r} against the job's {job}")
    depth = channel(oiio.ImageBuf(out), "ViewLayer.Depth.Z") if os.path.exists(out) else None
    nearest = float(command[command.index("--nearest") + 1].rstrip("m")) if command else None
    expect(depth is not None and nearest and abs(nearest / depth.min() - 1) < 0.1,
           f"estimate: nearest depth {nearest} from the rays, {depth.min() if depth is not None else None} "
           "in the depth pass")
    print(f"estimate: panel '{panel}'; job '{job[0] if job else None}'; nearest {nearest} m from rays, "
          f"{depth.min() if depth is not None else None} m in the depth pass", flush=True)
    # Max terms as a count: shown as one, a typed text that is none refused by name
    expect(w.max_terms_text == "4e12", f"max terms shown as {w.max_terms_text!r}, expected '4e12'")
    w.max_terms_text = "lots"
    refused("max_terms_text", "Max terms 'lots' is not a count of terms")
    w.max_terms_text = "1e13"
    expect(w.max_terms_text == "1e13" and abs(w.max_terms - 1e13) < 1e7, f"max terms 1e13: {w.max_terms_text}")
    # Device GPU with Summation NUFFT: refused before the render, in the panel's words
    w.device, w.summation = 'gpu', 'nufft'
    refused("gpu_nufft", "Device GPU with Summation NUFFT: the NUFFTs have no GPU evaluator")
    w.device, w.summation = 'cpu', 'auto'
    # beyond Max terms: refused before any work, pointing at the panel's settings and at
    # `wavecam farm` with the command to run
    w.max_terms_text = "1000"
    refused("max_terms", before=False, expected="beyond Max terms (1000): lower Runs, Wavelengths or the "
            "resolution, or raise Max terms; too large for one machine")
    farm = [e for e in errors if "wavecam farm submit " in e and " --tasks 2" in e]
    expect(len(farm) == 1, f"max terms: the farm command given; got {errors}")
    # Device GPU where the only Vulkan device is a software one (llvmpipe): said so (the
    # refusal's job line names the device, without any work done)
    w.device = 'gpu'
    render("software_vulkan")
    software = [e for e in errors if " on llvmpipe" in e or " on lavapipe" in e]
    warned = [i for i in infos if "a software Vulkan driver running on the processor" in i]
    expect(bool(software) == bool(warned), f"software vulkan: the job ran on {software}, the add-on said {infos}")
    print(f"software vulkan: {warned[0] if warned else 'no software Vulkan device here: ' + str(errors)}",
          flush=True)
    w.device = 'cpu'
    w.max_terms_text = "4e12"
    # the kernel summation, and the device
    w.summation = 'kernel'
    w.device = 'cpu'
    out = render("random_phase_kernel")
    spec = oiio.ImageInput.open(out).spec() if os.path.exists(out) else None
    expect(spec is not None and spec.getattribute("wavecam.summation") == "kernel", "kernel: wavecam.summation kernel")
    expect(spec is not None and str(spec.getattribute("wavecam.device")).startswith("cpu"), "kernel: wavecam.device cpu")
    if spec is not None:
        print(f"summation: {spec.getattribute('wavecam.summation')} on {spec.getattribute('wavecam.device')}",
              flush=True)


OLD_METHODS = [('fast', "Fast", ""), ('exact', "Exact", ""), ('incoherent', "Incoherent", "")]


def save_old_file(blend):
    """A .blend as the add-on saved it when the methods were 'fast'/'exact' and the wavelengths
    one text field: the same property group, defined as it was then (run without the add-on)."""
    class OldSettings(bpy.types.PropertyGroup):
        enabled: bpy.props.BoolProperty()
        wavelengths: bpy.props.StringProperty(default="8")
        method: bpy.props.EnumProperty(items=OLD_METHODS, default='fast')
    bpy.utils.register_class(OldSettings)
    bpy.types.Camera.wavecam = bpy.props.PointerProperty(type=OldSettings)
    listed = bpy.context.scene.camera.data
    listed.wavecam.method, listed.wavecam.wavelengths = 'exact', "450nm, 550nm,650nm"
    counted = bpy.data.cameras.new("Counted")
    counted.wavecam.method, counted.wavecam.wavelengths = 'fast', "5"
    counted.use_fake_user = True
    bpy.ops.wm.save_as_mainfile(filepath=blend)


def load_old_file():
    listed, counted = bpy.context.scene.camera.data.wavecam, bpy.data.cameras["Counted"].wavecam
    expect(listed.method == 'random-phase', f"old 'exact' loads as random-phase, not {listed.method}")
    expect(listed.use_wavelength_list and listed.wavelength_list == "450nm,550nm,650nm",
           f"old list loads as the list: {listed.use_wavelength_list} {listed.wavelength_list}")
    expect(counted.method == 'convolution', f"old 'fast' loads as convolution, not {counted.method}")
    expect(not counted.use_wavelength_list and counted.wavelength_count == 5,
           f"old count loads as the count: {counted.use_wavelength_list} {counted.wavelength_count}")
    expect("wavelengths" not in listed.keys(), "the old text field is gone")
    print(f"old file: {listed.method} {listed.wavelengths_text()}; {counted.method} {counted.wavelengths_text()}")


if step == "install":
    install(args[1], args[2])
elif step == "scene":
    make_scene(args[1], args[2], args[3])
elif step == "check":
    check([int(f) for f in args[1:]])
elif step == "errors":
    errors()
elif step == "settings":
    settings()
elif step == "oldfile":
    save_old_file(args[1])
elif step == "loadold":
    load_old_file()
if failures:
    print(f"{len(failures)} check(s) failed", flush=True)
    sys.exit(1)
