// wavecam as a compositing stage (docs/compositing.md): the radiance layer chosen as a whole,
// every other channel passed through in its own name and type, negative light refused or
// clamped, a second diffraction refused. Through `wavecam apply`, as a pipeline runs it.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
const std::string kQuick = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 ";
constexpr int kW = 16, kH = 12;

// Sets one channel of one pixel.
void set_channel(OIIO::ImageBuf& b, int i, int j, int, int c, float v) {
    std::vector<float> px(b.nchannels());
    b.getpixel(i, j, px.data(), int(px.size()));
    px[c] = v;
    b.setpixel(i, j, px.data(), int(px.size()));
}

// Channel c of pixel (i, j) of a plate with these names: every channel its own pattern, depth 3 m
// ("*.Z" and "Z"), a checker in the radiance so that diffraction changes it.
float plate_value(const std::string& name, int c, int i, int j) {
    if (name == "Z" || (name.size() > 2 && name.substr(name.size() - 2) == ".Z")) return 3.0f;
    if (name == "id") return float((i * 7 + j) % 5);
    return ((i / 2 + j / 2) % 2 ? 0.9f : 0.1f) * (1.0f + 0.1f * c) + 0.01f * float(i + j);
}

// A plate of these channels and per-channel types, at 40 deg, with extra header attributes.
void write_plate(const fs::path& path, const std::vector<std::string>& names, const std::vector<OIIO::TypeDesc>& types,
                 const std::map<std::string, std::string>& attributes = {}) {
    OIIO::ImageSpec spec(kW, kH, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.attribute("wavecam.fov", 40.0f);
    for (const auto& [k, v] : attributes) spec.attribute(k, v);
    OIIO::ImageBuf buf(spec);
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i)
            for (int c = 0; c < spec.nchannels; ++c) set_channel(buf, i, j, 0, c, plate_value(names[c], c, i, j));
    OIIO::ImageSpec file = spec;
    file.channelformats = types;
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), file));
    ASSERT_TRUE(buf.write(out.get()));
    out->close();
}

OIIO::ImageSpec file_spec(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path;
    return in ? in->spec() : OIIO::ImageSpec();
}

CommandRun apply(const fs::path& in, const fs::path& out, const std::string& extra = "") {
    return run_command(kWavecam + " apply " + in.string() + " -o " + out.string() + kQuick + extra);
}

// Whether channel `name` of a and b hold the same values at every pixel.
bool same_channel(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const std::string& name) {
    const int ca = a.spec().channelindex(name), cb = b.spec().channelindex(name);
    if (ca < 0 || cb < 0) return false;
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i)
            if (a.getchannel(i, j, 0, ca) != b.getchannel(i, j, 0, cb)) return false;
    return true;
}
}  // namespace

TEST(PlateChannels, AovsCryptomatteAndIdsPassThroughInTheirOwnNamesAndTypes) {
    const fs::path dir = scratch("plate_aovs");
    const OIIO::TypeDesc half = OIIO::TypeDesc::HALF, flt = OIIO::TypeDesc::FLOAT, u32 = OIIO::TypeDesc::UINT32;
    const std::vector<std::string> names = {"R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z", "crypto00.R", "crypto00.G",
                                            "crypto00.B", "crypto00.A", "diffuse.R", "diffuse.G", "diffuse.B", "id"};
    const std::vector<OIIO::TypeDesc> types = {half, half, half, half, flt, half, half, half, flt, flt,
                                               flt,  flt,  half, half, half, u32};
    write_plate(dir / "in.exr", names, types,
                {{"cryptomatte/0a1b2c3/name", "crypto00"}, {"cryptomatte/0a1b2c3/manifest", "{\"ball\":\"3f800000\"}"}});
    auto r = apply(dir / "in.exr", dir / "out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec in = file_spec(dir / "in.exr"), out = file_spec(dir / "out.exr");
    EXPECT_EQ(out.channelnames, in.channelnames);  // (OpenEXR's order: R, G, B, A, Z, then by name)
    for (int c = 0; c < out.nchannels; ++c) {
        const std::string& n = out.channelnames[c];
        const size_t k = std::find(names.begin(), names.end(), n) - names.begin();
        ASSERT_LT(k, names.size()) << n;
        EXPECT_EQ(out.channelformat(c), types[k]) << n << " kept its type";
    }
    EXPECT_EQ(out.get_string_attribute("cryptomatte/0a1b2c3/name"), "crypto00");
    EXPECT_EQ(out.get_string_attribute("wavecam.diffracted-channels"), "R,G,B,A");
    const OIIO::ImageBuf in_px = read_float(dir / "in.exr"), out_px = read_float(dir / "out.exr");
    for (const std::string& n : names) {
        const bool diffracted = n == "R" || n == "G" || n == "B" || n == "A";
        EXPECT_EQ(same_channel(in_px, out_px, n), !diffracted) << n;
    }

    // dropped on request, and Cryptomatte's manifest with its channels; the diffracted channels as float
    r = apply(dir / "in.exr", dir / "lean.exr", "--other-channels drop --pixel-type float");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec lean = file_spec(dir / "lean.exr");
    EXPECT_EQ(lean.channelnames, (std::vector<std::string>{"R", "G", "B", "A", "Z"}));
    for (int c = 0; c < lean.nchannels; ++c) EXPECT_EQ(lean.channelformat(c), flt) << lean.channelnames[c];
    EXPECT_EQ(lean.find_attribute("cryptomatte/0a1b2c3/name"), nullptr);
    fs::remove_all(dir);
}

TEST(PlateChannels, TheRadianceLayerIsChosenAsAWholeAndDepthFromItsViewLayer) {
    const fs::path dir = scratch("plate_layers");
    const OIIO::TypeDesc f = OIIO::TypeDesc::FLOAT;
    // AOV layers beside the beauty, no unnamed R, G, B: the beauty is the radiance
    const std::vector<std::string> aovs = {"albedo.R", "albedo.G", "albedo.B", "beauty.R", "beauty.G", "beauty.B", "Z"};
    write_plate(dir / "aovs.exr", aovs, std::vector<OIIO::TypeDesc>(aovs.size(), f));
    auto r = apply(dir / "aovs.exr", dir / "aovs_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf in = read_float(dir / "aovs.exr"), out = read_float(dir / "aovs_out.exr");
    EXPECT_TRUE(same_channel(in, out, "albedo.R"));
    EXPECT_FALSE(same_channel(in, out, "beauty.R"));
    EXPECT_EQ(out.spec().get_string_attribute("wavecam.layer"), "beauty");

    // two view layers: refused, naming both, until one is chosen; its depth is its own view layer's
    const std::vector<std::string> views = {"VL1.Combined.R", "VL1.Combined.G", "VL1.Combined.B", "VL1.Depth.Z",
                                            "VL2.Combined.R", "VL2.Combined.G", "VL2.Combined.B", "VL2.Depth.Z"};
    write_plate(dir / "views.exr", views, std::vector<OIIO::TypeDesc>(views.size(), f));
    {  // VL1's depth at 2 cm: nearer than the 0.2 mm pinhole can image, so a run that read it fails saying so
        OIIO::ImageBuf b = read_float(dir / "views.exr");
        for (int j = 0; j < kH; ++j)
            for (int i = 0; i < kW; ++i) set_channel(b, i, j, 0, 3, 0.0002f);
        ASSERT_TRUE(b.write((dir / "views.exr").string()));
    }
    r = apply(dir / "views.exr", dir / "views_out.exr");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("'VL1.Combined', 'VL2.Combined'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--layer"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "views_out.exr"));
    r = apply(dir / "views.exr", dir / "views_out.exr", "--layer VL2.Combined");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf vin = read_float(dir / "views.exr"), vout = read_float(dir / "views_out.exr");
    EXPECT_TRUE(same_channel(vin, vout, "VL1.Combined.R"));
    EXPECT_FALSE(same_channel(vin, vout, "VL2.Combined.R"));
    r = apply(dir / "views.exr", dir / "vl1_out.exr", "--layer VL1.Combined");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("channel 'VL1.Depth.Z'"), std::string::npos) << r.output;
    r = apply(dir / "views.exr", dir / "none_out.exr", "--layer VL3.Combined");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("layer 'VL3.Combined': no such layer"), std::string::npos) << r.output;
    fs::remove_all(dir);
}

TEST(PlateChannels, NegativeLightIsRefusedNamingThePixelOrClampedAndCounted) {
    const fs::path dir = scratch("plate_negative");
    const std::vector<std::string> names = {"R", "G", "B", "Z"};
    write_plate(dir / "in.exr", names, std::vector<OIIO::TypeDesc>(4, OIIO::TypeDesc::HALF));
    OIIO::ImageBuf b = read_float(dir / "in.exr");
    set_channel(b, 5, 4, 0, 1, 0.0f);
    ASSERT_TRUE(b.write((dir / "zero.exr").string(), OIIO::TypeDesc::HALF));
    set_channel(b, 5, 4, 0, 1, -65504.0f);  // a denoiser's half overshoot
    ASSERT_TRUE(b.write((dir / "negative.exr").string(), OIIO::TypeDesc::HALF));
    auto r = apply(dir / "negative.exr", dir / "out.exr");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("channel 'G' at pixel (5, 4) is -65504, expected radiance >= 0"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
    r = apply(dir / "negative.exr", dir / "out.exr", "--negative clamp");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("1 negative values clamped to 0"), std::string::npos) << r.output;
    r = apply(dir / "zero.exr", dir / "zero_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf clamped = read_float(dir / "out.exr"), zero = read_float(dir / "zero_out.exr");
    EXPECT_EQ(clamped.spec().get_string_attribute("wavecam.negative-clamped"), "1 values");
    for (const char* c : {"R", "G", "B"}) EXPECT_TRUE(same_channel(clamped, zero, c)) << c;
    fs::remove_all(dir);
}

// Colour that is not premultiplied (a TIFF's unassociated alpha) is premultiplied on reading:
// the same image as the premultiplied file, and the header says what was done.
TEST(PlateChannels, UnassociatedColourIsPremultipliedOnReading) {
    const fs::path dir = scratch("plate_unassociated");
    const std::vector<std::string> names = {"R", "G", "B", "A", "Z"};
    write_plate(dir / "plate.exr", names, std::vector<OIIO::TypeDesc>(5, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBuf straight = read_float(dir / "plate.exr");
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) set_channel(straight, i, j, 0, 3, i < kW / 2 ? 1.0f : 0.25f);
    OIIO::ImageBuf pre = straight;
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i)
            for (int c = 0; c < 3; ++c)
                set_channel(pre, i, j, 0, c, straight.getchannel(i, j, 0, c) * straight.getchannel(i, j, 0, 3));
    straight.specmod().alpha_channel = pre.specmod().alpha_channel = 3;
    straight.specmod().attribute("oiio:UnassociatedAlpha", 1);
    ASSERT_TRUE(straight.write((dir / "straight.tif").string()));
    ASSERT_TRUE(pre.write((dir / "pre.exr").string()));
    auto r = apply(dir / "straight.tif", dir / "straight_out.exr", "--depth-channel channel4 --fov 40deg");  // (TIFF keeps neither)
    ASSERT_EQ(r.status, 0) << r.output;
    r = apply(dir / "pre.exr", dir / "pre_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf a = read_float(dir / "straight_out.exr"), p = read_float(dir / "pre_out.exr");
    for (const char* c : {"R", "G", "B", "A"})
        for (int j = 0; j < kH; ++j)
            for (int i = 0; i < kW; ++i) {
                const int k = a.spec().channelindex(c);
                EXPECT_NEAR(a.getchannel(i, j, 0, k), p.getchannel(i, j, 0, k), 1e-3 * p.getchannel(i, j, 0, k) + 1e-6) << c << " " << i << "," << j;
            }
    EXPECT_NE(a.spec().get_string_attribute("wavecam.alpha").find("premultiplied by it on reading"), std::string::npos)
        << a.spec().get_string_attribute("wavecam.alpha");
    EXPECT_EQ(a.spec().get_int_attribute("tiff:UnassociatedAlpha", 0), 0);
    fs::remove_all(dir);
}

// The header's colour tells the truth both ways: an ACES file (AP0 chromaticities and the ACES
// container flag) is read as ACES2065-1, an AP1 file as ACEScg, unknown primaries are refused
// naming them; the output carries its own space's chromaticities, the ACES flag only for
// ACES2065-1, and oiio:ColorSpace.
TEST(PlateChannels, ChromaticitiesAndTheAcesFlagSetTheColourSpacesBothWays) {
    const fs::path dir = scratch("plate_colour");
    const std::vector<std::string> names = {"R", "G", "B", "Z"};
    write_plate(dir / "plain.exr", names, std::vector<OIIO::TypeDesc>(4, OIIO::TypeDesc::FLOAT));
    const float ap0[8] = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f};
    const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    const float rec2020[8] = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
    auto tagged = [&](const std::string& name, const float* xy, bool aces) {
        OIIO::ImageBuf b = read_float(dir / "plain.exr");
        b.specmod().attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy);
        if (aces) b.specmod().attribute("acesImageContainerFlag", 1);
        if (aces) b.specmod().attribute("compression", "dwaa");  // (lossy: only where nothing is compared bit for bit)
        EXPECT_TRUE(b.write((dir / name).string()));
    };
    tagged("aces.exr", ap0, true);
    tagged("ap1.exr", ap1, false);
    tagged("rec2020.exr", rec2020, false);

    auto r = apply(dir / "aces.exr", dir / "xyz.exr", "--output-colorspace CIE-XYZ-D65");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec xyz = file_spec(dir / "xyz.exr");
    EXPECT_EQ(xyz.get_string_attribute("wavecam.input-colorspace"), "ACES2065-1");
    EXPECT_EQ(xyz.get_int_attribute("acesImageContainerFlag", 0), 0);
    const OIIO::ParamValue* c = xyz.find_attribute("chromaticities");
    ASSERT_NE(c, nullptr);
    const float* v = static_cast<const float*>(c->data());
    EXPECT_FLOAT_EQ(v[0], 1.0f);  // X's primary at x = 1
    EXPECT_FLOAT_EQ(v[3], 1.0f);  // Y's at y = 1
    EXPECT_NEAR(v[6], 1.0f / 3, 1e-6);

    r = apply(dir / "aces.exr", dir / "aces_out.exr");  // kept in ACES2065-1: the flag stays, and the chromaticities
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec aces = file_spec(dir / "aces_out.exr");
    EXPECT_EQ(aces.get_int_attribute("acesImageContainerFlag", 0), 1);
    EXPECT_EQ(aces.get_string_attribute("compression"), "dwaa");  // the input's, kept (the default)

    // AP1 primaries without a name are ACEScg: the same image as naming it
    r = apply(dir / "ap1.exr", dir / "ap1_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    r = apply(dir / "plain.exr", dir / "named_out.exr", "--input-colorspace ACEScg");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(file_spec(dir / "ap1_out.exr").get_string_attribute("wavecam.input-colorspace"), "ACEScg");
    const OIIO::ImageBuf ap1_out = read_float(dir / "ap1_out.exr"), named = read_float(dir / "named_out.exr");
    for (const char* ch : {"R", "G", "B"}) EXPECT_TRUE(same_channel(ap1_out, named, ch)) << ch;

    // primaries wavecam cannot place are refused, naming them, unless the space is named
    r = apply(dir / "rec2020.exr", dir / "bt2020_out.exr");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("chromaticities (0.708, 0.292"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--input-colorspace"), std::string::npos) << r.output;
    r = apply(dir / "rec2020.exr", dir / "bt2020_out.exr", "--input-colorspace lin_rec709");
    EXPECT_EQ(r.status, 0) << r.output;
    fs::remove_all(dir);
}

// Anamorphic pixels (PixelAspectRatio 2: twice as wide as tall). A star's blur is the pinhole's
// round disc in the film's own units, so its second moments across and along, less the star's
// pixel and the film's pixel (each a box: width^2/12 twice), are equal; taking the pixels as
// square would make the blur twice as wide as tall after desqueeze (moments 4:1).
TEST(PlateChannels, AnAnamorphicStarComesBackRoundAfterDesqueeze) {
    const fs::path dir = scratch("plate_anamorphic");
    constexpr int w = 24, h = 48;  // a square frame: 48 x 48 in the film's units
    auto star = [&](const std::string& name, float aspect) {
        OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "Z"};
        spec.attribute("wavecam.fov", 40.0f);
        spec.attribute("PixelAspectRatio", aspect);
        OIIO::ImageBuf b(spec);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const float v = i == w / 2 && j == h / 2 ? 100.0f : 0.0f, px[4] = {v, v, v, 1e10f};
                b.setpixel(i, j, px);
            }
        ASSERT_TRUE(b.write((dir / name).string()));
    };
    star("wide.exr", 2.0f);
    star("square.exr", 1.0f);
    // a 3 mm pinhole at 20 mm: a geometric disc about 10 film pixels across
    auto run = [&](const std::string& in, const std::string& out) {
        return run_command(kWavecam + " apply " + (dir / in).string() + " -o " + (dir / out).string() +
                           " --film-distance 20mm --pinhole 3mm --no-vignetting --monochrome");
    };
    auto r = run("wide.exr", "wide_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    r = run("square.exr", "square_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    // second moments in the film's units: a pixel is `aspect` wide and 1 tall
    auto moments = [&](const fs::path& path, double aspect, double& across, double& along) {
        const OIIO::ImageBuf b = read_float(path);
        EXPECT_EQ(b.spec().width, w);
        double sum = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const double v = b.getchannel(i, j, 0, 1), x = (i + 0.5) * aspect, y = j + 0.5;
                sum += v, sx += v * x, sy += v * y, sxx += v * x * x, syy += v * y * y;
            }
        across = sxx / sum - std::pow(sx / sum, 2) - 2 * aspect * aspect / 12;
        along = syy / sum - std::pow(sy / sum, 2) - 2.0 / 12;
        return sum;
    };
    double across, along, square_across, square_along;
    const double energy = moments(dir / "wide_out.exr", 2.0, across, along);
    moments(dir / "square_out.exr", 2.0, square_across, square_along);  // the same pixels taken as square
    std::printf("second moments across/along: %.3f (square pixels assumed: %.3f), light %.2f of 100\n", across / along,
                square_across / square_along, energy);
    EXPECT_NEAR(across / along, 1.0, 0.15) << across << " " << along;
    EXPECT_GT(square_across / square_along, 2.5) << square_across << " " << square_along;
    EXPECT_NEAR(energy, 100.0, 3.0);  // the star's light, kept (no vignetting)
    EXPECT_FLOAT_EQ(file_spec(dir / "wide_out.exr").get_float_attribute("PixelAspectRatio"), 2.0f);
    fs::remove_all(dir);
}
