#include "wavecam/render_input.h"

#include "multi_view.h"
#include "render_parts.h"
#include "render_windows.h"
#include "wavecam/scene_diffraction.h"

#include <OpenImageIO/strutil.h>

#include <limits.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "wavecam/units.h"

namespace wavecam {
namespace {

// The header's horizontal field of view in radians (0 when the attribute is absent). Degrees as
// a float or an int (`oiiotool --attrib wavecam.fov 40` writes an int), or a string: a bare
// number in degrees ("40") or an angle with its unit ("40deg", "0.7rad").
Result<double> header_fov(const OIIO::ImageSpec& spec) {
    const OIIO::ParamValue* p = spec.find_attribute(kFovAttribute);
    if (!p) return Result<double>::success(0);
    const OIIO::TypeDesc t = p->type();
    const bool scalar = t.aggregate == OIIO::TypeDesc::SCALAR && t.arraylen == 0;
    Result<double> fov = Result<double>::failure(std::string(kFovAttribute) +
                                                 ": expected degrees as a number or a string such as \"40deg\", "
                                                 "got a value of type " + t.c_str());
    if (t == OIIO::TypeDesc::STRING) {
        const std::string text = p->get_string();
        char* end = nullptr;
        const double deg = std::strtod(text.c_str(), &end);
        fov = !text.empty() && *end == '\0' ? Result<double>::success(deg * M_PI / 180.0)
                                             : parse_angle(text, kFovAttribute);
    } else if (scalar && t.is_floating_point()) {
        fov = Result<double>::success(p->get_float() * M_PI / 180.0);
    } else if (scalar && t.basetype >= OIIO::TypeDesc::UINT8 && t.basetype <= OIIO::TypeDesc::INT64) {
        // (OIIO 2.4's get_float reads an int attribute as 0)
        fov = Result<double>::success(p->get_int() * M_PI / 180.0);
    }
    if (fov.ok() && !(fov.value > 0 && fov.value < M_PI))
        return Result<double>::failure(std::string(kFovAttribute) + " is " + OIIO::Strutil::fmt::format("{:g}", fov.value * 180 / M_PI) +
                                       " degrees, expected a field of view between 0 and 180 degrees");
    return fov;
}

// OpenEXR's screen window: the projection that made the frame. Its centre off (0, 0) is a
// lens-shifted render, the optical axis off the frame's centre, which wavecam's camera (axis at
// the display window's centre: the PSF's field stretch and the vignetting follow it) cannot
// hold; a width other than 1 is a zoomed projection that the fov read from the file does not
// describe. Both are refused, naming the attribute ("" when the frame is centred).
std::string off_axis_projection(const OIIO::ImageSpec& spec, bool fov_given) {
    float centre[2] = {0, 0}, width = 1;
    const bool has_centre = spec.getattribute("screenWindowCenter", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::VEC2), centre);
    spec.getattribute("screenWindowWidth", OIIO::TypeDesc::FLOAT, &width);
    if (has_centre && (std::fabs(centre[0]) > 1e-6f || std::fabs(centre[1]) > 1e-6f))
        return OIIO::Strutil::fmt::format(
            "screenWindowCenter is ({:g}, {:g}): a lens-shifted frame, its optical axis off the frame's centre; "
            "expected (0, 0): wavecam's pinhole sits on the axis through the frame's centre (the PSF's stretch and "
            "the vignetting follow it). Render without shift, on a frame wide enough to hold the shifted one, and "
            "crop the diffracted image",
            centre[0], centre[1]);
    if (!fov_given && std::fabs(width - 1.0f) > 1e-6f)
        return OIIO::Strutil::fmt::format(
            "screenWindowWidth is {:g}: a projection zoomed against the frame, which the file's field of view does "
            "not describe; expected 1, or the fov setting giving the frame's own horizontal field of view", width);
    return {};
}

// What to do when the file carries no field of view; a Blender render is told how to get one.
// The front says how its users give the fov (ErrorKind::Missing, field "fov").
std::string missing_fov_message(const OIIO::ImageSpec& spec) {
    std::string m = std::string("no field of view: the file has no '") + kFovAttribute +
                    "' attribute, and no fov setting was given";
    bool blender = spec.find_attribute("BlenderMultiChannel") != nullptr;
    for (const std::string& n : spec.channelnames) blender = blender || OIIO::Strutil::ends_with(n, "Combined.R");
    if (blender)
        m += ". For a Blender render: install and enable wavecam's Blender add-on "
             "(share/wavecam/blender/wavecam_blender.zip; it writes " + std::string(kFovAttribute) +
             " into each frame and runs wavecam), or set the fov to 2*atan(x/z) in degrees with x, z of the widest "
             "corner of camera.data.view_frame(scene=scene) (that is 2*atan(sensor_width/2/lens) only for a landscape "
             "frame with sensor fit Auto or Horizontal and no shift)";
    return m;
}

// Each channel read once, straight into its place in the plain arrays.
bool read_channels(const OIIO::ImageBuf& image, const RenderChannels& ch, RenderInput& in) {
    auto read = [&](int c, float* into, int stride) {
        OIIO::ROI roi = image.roi();
        roi.chbegin = c;
        roi.chend = c + 1;
        return image.get_pixels(roi, OIIO::TypeDesc::FLOAT, into, stride * sizeof(float),
                                stride * sizeof(float) * in.width);
    };
    const size_t n = size_t(in.width) * in.height;
    in.rgb.resize(3 * n);
    in.depth.resize(n);
    if (ch.alpha >= 0) in.alpha.resize(n);
    return read(ch.r, in.rgb.data(), 3) && read(ch.g, in.rgb.data() + 1, 3) && read(ch.b, in.rgb.data() + 2, 3) &&
           read(ch.depth, in.depth.data(), 1) && (ch.alpha < 0 || read(ch.alpha, in.alpha.data(), 1));
}

// Light is never negative: a negative value (a denoiser's overshoot, a -65504 half) would be
// spread over every pixel its PSF reaches. Nor is coverage: a negative alpha would take light
// away where the element is laid over a plate. The first is refused, naming its channel and
// pixel; with `clamp`, every one is set to 0 and counted.
std::string clamp_or_refuse_negative(RenderInput& in, const OIIO::ImageSpec& spec, const RenderChannels& ch, bool clamp) {
    auto refuse = [&](int channel, size_t p, float v, const char* what, const char* why) {
        return "channel '" + spec.channelnames[channel] + "' at pixel (" + std::to_string(spec.x + int(p % in.width)) +
               ", " + std::to_string(spec.y + int(p / in.width)) + ") is " + OIIO::Strutil::fmt::format("{:g}", v) +
               ", expected " + what + " >= 0 (" + why + "; the negative setting 'clamp' sets such values to 0)";
    };
    const int rgb[3] = {ch.r, ch.g, ch.b};
    for (size_t k = 0; k < in.rgb.size(); ++k) {
        if (!(in.rgb[k] < 0)) continue;
        if (!clamp) return refuse(rgb[k % 3], k / 3, in.rgb[k], "radiance", "light is never negative");
        in.rgb[k] = 0;
        ++in.clamped;
    }
    for (size_t p = 0; p < in.alpha.size(); ++p) {
        if (!(in.alpha[p] < 0)) continue;
        if (!clamp) return refuse(ch.alpha, p, in.alpha[p], "coverage", "alpha is never negative");
        in.alpha[p] = 0;
        ++in.clamped;
    }
    return {};
}

// Alpha is coverage, and the radiance premultiplied by it (OpenEXR's rule). OIIO premultiplies
// a TIFF's or PNG's unassociated colour as it reads it, and says so (tiff:UnassociatedAlpha);
// an image read with OIIO's hint to keep it unassociated says oiio:UnassociatedAlpha, and is
// premultiplied here. Either way the output notes it.
void premultiply_unassociated(const OIIO::ImageSpec& spec, RenderInput& in) {
    if (in.alpha.empty()) return;
    if (spec.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0) {
        for (size_t p = 0; p < in.alpha.size(); ++p)
            for (int c = 0; c < 3; ++c) in.rgb[3 * p + c] *= in.alpha[p];
        in.premultiplied_on_reading = true;
    }
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        if (OIIO::Strutil::ends_with(p.name().string(), ":UnassociatedAlpha") && spec.get_int_attribute(p.name(), 0) != 0)
            in.premultiplied_on_reading = true;
}

// A file wavecam wrote, named by what its header says of the first diffraction.
std::string already_diffracted(const OIIO::ImageSpec& spec) {
    std::string job = "method " + std::string(spec.get_string_attribute("wavecam.method"));
    for (const char* key : {"pinhole", "film-distance", "summary"})
        if (const std::string v = spec.get_string_attribute(std::string("wavecam.") + key); !v.empty())
            job += std::string(", ") + key + " " + v;
    if (const std::string v = spec.get_string_attribute("wavecam.job"); !v.empty()) job += ", job " + v;
    return "already diffracted by wavecam (" + job + "): a second diffraction would blur it twice; expected a render "
           "from an ideal pinhole, or the diffract-again setting to diffract it once more";
}

// The job's one check of the pixels: radiance finite, depth > 0; the first bad one named by its
// channel and pixel, in the file's pixel coordinates ("" when all are good).
std::string bad_pixel(const RenderInput& in, const OIIO::ImageSpec& spec, const RenderChannels& ch) {
    const int rgb[3] = {ch.r, ch.g, ch.b};
    for (size_t p = 0; p < in.depth.size(); ++p) {
        auto where = [&](const std::string& channel) {
            return "channel '" + channel + "' at pixel (" + std::to_string(spec.x + int(p % in.width)) + ", " +
                   std::to_string(spec.y + int(p / in.width)) + ")";
        };
        for (int c = 0; c < 3; ++c)
            if (const float v = in.rgb[3 * p + c]; !radiance_in_range(v))
                return where(spec.channelnames[rgb[c]]) + " is " + OIIO::Strutil::fmt::format("{:g}", v) +
                       ", expected finite radiance within +-1e30";
        if (!in.alpha.empty() && !std::isfinite(in.alpha[p]))
            return where(spec.channelnames[ch.alpha]) + " is " + OIIO::Strutil::fmt::format("{:g}", in.alpha[p]) +
                   ", expected a finite coverage";
        const float d = in.depth[p];
        if (!depth_in_range(d))
            return where(in.depth_channel) + " is " + OIIO::Strutil::fmt::format("{:g}", d) +
                   ", expected a distance > 0 (inf or >= 1e9 for sky)";
    }
    return {};
}

}  // namespace

Result<RenderInput> load_render(const OIIO::ImageBuf& image, const std::string& name, const RenderReadOptions& opt) {
    auto fail = [&name](const std::string& m, ErrorKind kind = ErrorKind::Failed, const std::string& field = {}) {
        return Result<RenderInput>::failure(name + ": " + m, kind, field);
    };
    const OIIO::ImageSpec& spec = image.spec();
    if (spec.width < 2 || spec.height < 2)
        return fail("image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    ", expected at least 2x2 pixels");
    if (spec.depth > 1) return fail("volume images are not supported, expected a 2D image");
    if (spec.deep) return fail("deep image (samples per pixel) is not supported, expected a flat image");
    // (DiffractPlan::diffract takes anamorphic frames to square pixels before they reach here)
    if (const float aspect = spec.get_float_attribute("PixelAspectRatio", 1.0f); aspect != 1.0f)
        return fail("pixel aspect ratio " + OIIO::Strutil::fmt::format("{:g}", aspect) +
                    ": a share of a job (apply --share, farm) is computed on square pixels; expected square pixels, "
                    "or the whole frame diffracted in one run (wavecam apply, the plugin)");
    // (DiffractPlan::diffract takes each view of a multi-view file alone, multi_view.h)
    if (const std::vector<std::string> views = detail::view_names(spec); !views.empty())
        return fail("a multi-view (stereo) file, views " + OIIO::Strutil::join(views, ", ") +
                    ": a share of a job (apply --share, farm) reads one view; expected a single-view file, or the whole "
                    "file diffracted in one run (wavecam apply, the plugin), each view with its own depth");
    if (spec.find_attribute("wavecam.summary") && !opt.diffract_again)
        return fail(already_diffracted(spec), ErrorKind::Invalid, "diffract-again");
    auto found = find_render_channels(spec, opt);
    if (!found.ok()) return fail(found.error, found.kind, found.field);
    const RenderChannels& ch = found.value;
    const std::string channels = OIIO::Strutil::join(spec.channelnames, ", ");
    if (ch.r < 0 || ch.g < 0 || ch.b < 0)
        return fail("channels R, G, B: not found (channels: " + channels + "), expected linear RGB radiance" +
                    detail::other_part_note(image, ch.r < 0 ? "R" : ch.g < 0 ? "G" : "B"));
    if (ch.depth < 0) {
        // in another part, naming a depth channel cannot help: the note says what does
        const std::string elsewhere = detail::other_part_note(image, opt.depth_channel);
        return fail("channel '" + opt.depth_channel + "': not found (channels: " + channels +
                        "), expected a depth channel" + elsewhere,
                    elsewhere.empty() ? ErrorKind::Missing : ErrorKind::Failed, "depth-channel");
    }

    RenderInput in;
    in.width = spec.width;
    in.height = spec.height;
    in.channels = ch;
    in.depth_channel = spec.channelnames[ch.depth];
    in.colour.colorspace = spec.get_string_attribute("oiio:ColorSpace");
    if (const OIIO::ParamValue* c = spec.find_attribute("chromaticities"); c && c->type().basetype == OIIO::TypeDesc::FLOAT &&
                                                                           c->type().numelements() * c->type().aggregate == 8)
        in.colour.chromaticities.assign(static_cast<const float*>(c->data()), static_cast<const float*>(c->data()) + 8);
    in.colour.aces_container = spec.get_int_attribute("acesImageContainerFlag", 0) == 1;
    if (!read_channels(image, ch, in)) return fail("cannot read pixels: " + image.geterror());
    if (const std::string bad = bad_pixel(in, spec, ch); !bad.empty()) return fail(bad);
    if (const std::string bad = clamp_or_refuse_negative(in, spec, ch, opt.clamp_negative); !bad.empty())
        return fail(bad, ErrorKind::Invalid, "negative");
    premultiply_unassociated(spec, in);
    // Depth in metres: the file's units times the depth scale (1cm for a scene modelled in
    // centimetres). Sky is judged on the file's own value, before scaling.
    if (!(opt.depth_scale > 0 && std::isfinite(opt.depth_scale)))
        return fail("depth scale " + OIIO::Strutil::fmt::format("{:g}", opt.depth_scale) +
                    " m, expected a length > 0", ErrorKind::Invalid, "depth-scale");
    // A file whose depth was scaled to metres when it was made says so (render_pov.sh
    // --depth-scale writes wavecam.scene-unit): a second scale would shrink it again.
    if (const std::string unit = spec.get_string_attribute(kSceneUnitAttribute); !unit.empty() && opt.depth_scale != 1.0)
        return fail("its depth is in metres already (" + std::string(kSceneUnitAttribute) + " " + unit +
                        ": one scene unit was " + unit + " when it was made), and a depth scale of " +
                        with_unit(opt.depth_scale, 1.0, "m") + " would scale it again; expected no depth-scale setting",
                    ErrorKind::Invalid, "depth-scale");
    if (opt.depth_scale != 1.0)
        for (float& d : in.depth)
            if (d < kInfiniteDepth) d = static_cast<float>(d * opt.depth_scale);

    if (const std::string shifted = off_axis_projection(spec, opt.fov_h > 0); !shifted.empty())
        return fail(shifted);
    if (opt.fov_h > 0) {
        in.fov_h = opt.fov_h;
        in.fov_from = opt.fov_from;
    } else {
        auto fov = header_fov(spec);
        if (!fov.ok()) return fail(fov.error);
        if (fov.value == 0) return fail(missing_fov_message(spec), ErrorKind::Missing, "fov");
        in.fov_h = fov.value;
        in.fov_from = std::string("the file's ") + kFovAttribute + " attribute";
    }
    if (auto placed = detail::place_on_frame(spec, in); !placed.ok()) return fail(placed.error);
    return Result<RenderInput>::success(std::move(in));
}

namespace {

// What a name that exists but is no file is ("" for a regular file, or a name not on disk: OIIO
// says what that is, and a name such as "a.exr.wavecam?runs=8" is opened through a plugin).
// Refused before reading: a FIFO or a device (/dev/zero, /dev/urandom) would block or never
// end, a folder is no image.
std::string not_a_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        // (a name with settings, "a.exr.wavecam?runs=8", is not on disk: the plugin reads it)
        if (errno != ENAMETOOLONG || path.find('?') != std::string::npos)
            return errno == ENOENT || errno == ENOTDIR || errno == ENAMETOOLONG ? "" : std::strerror(errno);
        for (size_t start = 0; start <= path.size();) {
            const size_t end = std::min(path.find('/', start), path.size());
            if (end - start > NAME_MAX)
                return "a file or folder name of " + std::to_string(end - start) +
                       " characters, beyond the file system's limit of " + std::to_string(NAME_MAX) + " (NAME_MAX)";
            start = end + 1;
        }
        return "a path of " + std::to_string(path.size()) + " characters, beyond the limit of " +
               std::to_string(PATH_MAX - 1) + " (PATH_MAX)";
    }
    if (S_ISREG(st.st_mode)) {
        // a file that cannot be opened or read (permissions, an I/O error) says so, not that it is no image
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return std::strerror(errno);
        char byte = 0;
        const std::string why = ::read(fd, &byte, 1) < 0 ? std::strerror(errno) : "";
        ::close(fd);
        return why;
    }
    const char* what = S_ISDIR(st.st_mode)    ? "a folder"
                       : S_ISFIFO(st.st_mode) ? "a named pipe (FIFO)"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a regular file";
    return std::string(what) + "; expected an image file";
}

}  // namespace

Result<OIIO::ImageBuf> read_render(const std::string& path, const std::string& subimage, double max_bytes) {
    if (!not_a_file(path).empty()) return read_image(path, max_bytes);  // (which says what it is)
    auto part = detail::choose_part(path, subimage);
    if (!part.ok()) return Result<OIIO::ImageBuf>::failure(part);
    return read_image(path, max_bytes, part.value);
}

Result<OIIO::ImageBuf> read_image(const std::string& path, double max_bytes, int subimage) {
    if (const std::string why = not_a_file(path); !why.empty())
        return Result<OIIO::ImageBuf>::failure((path.size() > 200 ? path.substr(0, 40) + "..." : path) +
                                               ": cannot be read as an image (" + why + ")");
    OIIO::ImageBuf image(path);
    // the header first: what reading the pixels would take
    if (image.init_spec(path, subimage, 0)) {
        const OIIO::ImageSpec& spec = image.spec();
        const double bytes = double(spec.width) * spec.height * std::max(1, spec.depth) * spec.nchannels * sizeof(float);
        if (bytes > max_bytes) {
            std::ostringstream m;
            m << path << ": " << spec.width << "x" << spec.height << " pixels x " << spec.nchannels
              << " channels need about " << bytes / (1 << 20) << " MiB to read, beyond the max-memory limit of "
              << max_bytes / (1 << 20) << " MiB; a corrupt header, or raise max-memory";
            return Result<OIIO::ImageBuf>::failure(m.str(), ErrorKind::TooLarge, "max-memory");
        }
    }
    const bool read = image.read(subimage, 0, true, OIIO::TypeDesc::FLOAT);
    if (read && !image.deep()) return Result<OIIO::ImageBuf>::success(std::move(image));
    // deep pixels hold lists of samples, not one value each: no pixel access wavecam makes fits them
    const std::string why = read ? "a deep image; expected a flat one" : image.geterror();
    return Result<OIIO::ImageBuf>::failure(path + ": cannot be read as an image" + (why.empty() ? "" : " (" + why + ")"));
}

}  // namespace wavecam
