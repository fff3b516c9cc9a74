// The OIIO plugin's parts on their own: the names' ?KEY=VALUE items, which file a name stands
// for, and the bounded cache of computed images.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <fstream>

#include "command_runner.h"
#include "imageio/name_query.h"
#include "imageio/result_cache.h"
#include "imageio/source_identity.h"

namespace fs = std::filesystem;
using namespace wavecam::plugin;

TEST(NameQuery, ItemsArePercentDecodedKeysAndValues) {
    const auto r = split_query("my shot.exr.wavecam?pinhole=0.2mm&aperture=mask:my%20mask.png&pin%68ole2=%25%3d%26+");
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_EQ(r.value.path, "my shot.exr.wavecam");
    const wavecam::front::Settings expected = {
        {"pinhole", "0.2mm"}, {"aperture", "mask:my mask.png"}, {"pinhole2", "%=&+"}};
    EXPECT_EQ(r.value.settings, expected);
    const auto plain = split_query("shot.exr.wavecam");
    ASSERT_TRUE(plain.ok());
    EXPECT_EQ(plain.value.path, "shot.exr.wavecam");
    EXPECT_TRUE(plain.value.settings.empty());
}

TEST(NameQuery, MistakesAreRefusedNamingTheNameAndWhatWasExpected) {
    const struct {
        std::string name, message;
    } rows[] = {
        {"s.exr.wavecam?runs=8&runs=2", "s.exr.wavecam?runs=8&runs=2: ?runs= given twice; give each setting once"},
        {"s.exr.wavecam?runs=8&ru%6Es=2", "?runs= given twice; give each setting once"},
        {"s.exr.wavecam?pinhole=0.2%zzmm",
         "s.exr.wavecam?pinhole=0.2%zzmm: '%zz' in 'pinhole=0.2%zzmm' is not a percent escape; expected % and two "
         "hex digits, e.g. %20 for a space"},
        {"s.exr.wavecam?pinhole=0.2mm%2", "'%2' in 'pinhole=0.2mm%2' is not a percent escape"},
        {"s.exr.wavecam?p%g1nhole=0.2mm", "'%g1' in 'p%g1nhole=0.2mm' is not a percent escape"},
        {"s.exr.wavecam?runs=8&",
         "s.exr.wavecam?runs=8&: an empty item after '?' or '&' (a trailing or doubled '&'); expected KEY=VALUE "
         "items joined by &, e.g. ?pinhole=0.2mm&runs=8"},
        {"s.exr.wavecam?runs=8&&pinhole=0.2mm", "an empty item after '?' or '&'"},
        {"s.exr.wavecam?=8", "s.exr.wavecam?=8: '=8' has no setting name; expected KEY=VALUE items joined by &"},
        {"s.exr.wavecam?monochrome", "'monochrome' has no '=' and value; expected KEY=VALUE items joined by &"},
    };
    for (const auto& row : rows) {
        const auto r = split_query(row.name);
        EXPECT_FALSE(r.ok()) << row.name;
        EXPECT_NE(r.error.find(row.message), std::string::npos) << row.name << ": " << r.error;
    }
}

namespace {
void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
}  // namespace

// A file written again (same name, same size) or the same relative name in another working
// folder is another source; a wavecam name not on disk stands for the file under it.
TEST(SourceIdentity, FollowsTheFileAndItsVersionNotTheName) {
    const fs::path dir = wavecam::test::scratch("source_identity");
    fs::create_directories(dir / "a");
    fs::create_directories(dir / "b");
    write_text(dir / "a" / "shot.exr", "first");
    write_text(dir / "b" / "shot.exr", "first");
    const fs::path was = fs::current_path();
    fs::current_path(dir / "a");
    const std::string in_a = source_identity("shot.exr");
    EXPECT_FALSE(in_a.empty());
    EXPECT_EQ(source_identity("./shot.exr"), in_a);
    EXPECT_EQ(source_identity(dir / "a" / "shot.exr"), in_a);
    EXPECT_EQ(source_identity("shot.exr.wavecam?runs=8&pinhole=0.2mm"), in_a);
    EXPECT_EQ(source_identity("shot.exr.wavecam.wavecam"), in_a);
    EXPECT_EQ(source_identity("missing.exr.wavecam"), "");
    EXPECT_EQ(in_a.rfind((dir / "a" / "shot.exr").string(), 0), 0u) << in_a;  // absolute, whatever the working folder
    fs::current_path(dir / "b");
    EXPECT_NE(source_identity("shot.exr"), in_a);
    fs::current_path(dir / "a");
    // Another version: written again with the same length, its time a nanosecond on (the kernel
    // stamps writes at its clock tick, a few milliseconds: two same-length writes within one
    // tick are one version to any check by time); another length; a file renamed over it.
    const auto written = fs::last_write_time("shot.exr");
    write_text("shot.exr", "again");
    fs::last_write_time("shot.exr", written + std::chrono::nanoseconds(1));
    const std::string rewritten = source_identity("shot.exr");
    EXPECT_NE(rewritten, in_a);
    fs::last_write_time("shot.exr", written);
    write_text("shot.exr", "longer");
    fs::last_write_time("shot.exr", written);
    EXPECT_NE(source_identity("shot.exr"), in_a);
    write_text("other.exr", "first");
    fs::last_write_time("other.exr", written);
    const std::string before_rename = source_identity("shot.exr");
    fs::rename("other.exr", "shot.exr");
    EXPECT_NE(source_identity("shot.exr"), before_rename);
    // a description file is its own source, however its name ends
    write_text(dir / "a" / "shot.wavecam", "source = \"shot.exr\"\n");
    EXPECT_EQ(source_identity("shot.wavecam?runs=2"), source_identity("shot.wavecam"));
    EXPECT_NE(source_identity("shot.wavecam"), source_identity("shot.exr"));
    fs::current_path(was);
    fs::remove_all(dir);
}

namespace {
// An image of `megabytes` MiB of float pixels (256 x 256 x 4 floats = 1 MiB).
ResultCache::Image image_of(int megabytes) {
    return std::make_shared<const OIIO::ImageBuf>(OIIO::ImageSpec(256, 256 * megabytes, 4, OIIO::TypeDesc::FLOAT));
}
}  // namespace

TEST(ResultCache, KeepsTheMostRecentlyUsedWithinItsBounds) {
    ResultCache cache(3, size_t(4) << 20);
    const auto a = image_of(1), b = image_of(1), c = image_of(1), d = image_of(1);
    cache.insert("a", a);
    cache.insert("b", b);
    cache.insert("c", c);
    EXPECT_EQ(cache.entries(), 3u);
    EXPECT_EQ(cache.bytes(), size_t(3) << 20);
    EXPECT_EQ(cache.find("a"), a);  // now the most recently used: b goes first
    cache.insert("d", d);
    EXPECT_EQ(cache.entries(), 3u);
    EXPECT_EQ(cache.find("b"), nullptr);
    EXPECT_EQ(cache.find("a"), a);
    EXPECT_EQ(cache.find("c"), c);
    EXPECT_EQ(cache.find("d"), d);
    // the same key again replaces its image, counted once
    const auto a2 = image_of(2);
    cache.insert("a", a2);
    EXPECT_EQ(cache.find("a"), a2);
    EXPECT_EQ(cache.entries(), 3u);
    EXPECT_EQ(cache.bytes(), size_t(4) << 20);
}

TEST(ResultCache, ManyFramesStayUnderTheByteBudget) {
    const size_t budget = size_t(8) << 20;
    ResultCache cache(1000, budget);
    for (int frame = 0; frame < 100; ++frame) {
        cache.insert("frame " + std::to_string(frame), image_of(1 + frame % 3));
        EXPECT_LE(cache.bytes(), budget) << frame;
        EXPECT_NE(cache.find("frame " + std::to_string(frame)), nullptr) << frame;  // the newest is always kept
    }
    EXPECT_EQ(cache.find("frame 0"), nullptr);
    EXPECT_GE(cache.entries(), 3u);
}

TEST(ResultCache, TheNewestIsKeptEvenBeyondTheBudget) {
    ResultCache cache(4, size_t(2) << 20);
    cache.insert("small", image_of(1));
    const auto big = image_of(3);
    cache.insert("big", big);
    EXPECT_EQ(cache.entries(), 1u);
    EXPECT_EQ(cache.find("big"), big);
    EXPECT_EQ(cache.find("small"), nullptr);
    EXPECT_EQ(cache.bytes(), size_t(3) << 20);
}
