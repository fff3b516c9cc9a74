#include "wavecam/atomic_write.h"

#include <algorithm>

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

namespace wavecam {
namespace {
namespace fs = std::filesystem;

// The temporary being written now, for a signal handler to remove (temporary_being_written).
char g_temporary[PATH_MAX + 1];
std::atomic<bool> g_temporary_set{false};

struct TemporaryMark {
    explicit TemporaryMark(const fs::path& temp) {
        const std::string s = temp.string();
        if (s.size() > PATH_MAX) return;
        g_temporary_set.store(false);
        std::memcpy(g_temporary, s.c_str(), s.size() + 1);
        g_temporary_set.store(true);
    }
    ~TemporaryMark() { g_temporary_set.store(false); }
};

// Beside the target, hidden, the real extension last so OIIO picks the right writer:
// "dir/.out.exr.tmp12345.exr"; a name too long for that (a file name near NAME_MAX) gets the
// short ".wavecam.tmp12345.exr".
fs::path temporary_for(const fs::path& target) {
    const std::string pid = std::to_string(::getpid()), ext = target.extension().string();
    std::string name = "." + target.filename().string() + ".tmp" + pid + ext;
    if (name.size() > NAME_MAX) name = ".wavecam.tmp" + pid + ext;
    return target.parent_path() / name;
}

// Why a write failed, completed: a reason the writer did not give, and a full disk named.
std::string reason(std::string why, const fs::path& temp) {
    if (why.empty()) why = "the writer gave no reason";
    struct statvfs fs {};
    const fs::path dir = temp.parent_path().empty() ? fs::path(".") : temp.parent_path();
    if (::statvfs(dir.c_str(), &fs) == 0 && fs.f_bavail == 0) why += "; the disk is full";
    return why;
}

// Whatever fails, no temporary is left behind.
Result<bool> discard(const fs::path& temp, const std::string& message) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return Result<bool>::failure(message);
}

// Flushes the finished temporary to the disk: what the disk could not take fails here (and
// the target keeps its old content).
std::string sync_file(const fs::path& temp) {
    const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::strerror(errno);
    const bool synced = ::fsync(fd) == 0 || errno == EINVAL || errno == EROFS;  // (files that cannot be synced)
    const std::string why = synced ? "" : std::strerror(errno);
    ::close(fd);
    return why;
}

std::atomic<bool (*)()> g_cancelled{nullptr};

// Renames the finished temporary over the target (unless the process was asked to stop).
Result<bool> move_into_place(const fs::path& temp, const std::string& path) {
    if (bool (*cancelled)() = g_cancelled.load(); cancelled && cancelled())
        return discard(temp, path + ": interrupted; not written");
    std::error_code ec;
    fs::rename(temp, path, ec);
    return ec ? discard(temp, path + ": cannot move the finished file into place: " + ec.message())
              : Result<bool>::success(true);
}

// Reads the temporary's first and last rows back (of scanlines, or of tiles): a writer that
// loses bytes without saying so (a full disk under some of OIIO's writers) leaves a file whose
// end does not read back. (Not the whole image: decoding it again cost a 1080p frame's write a
// third of its time.)
std::string read_back(const fs::path& temp, const OIIO::ImageSpec& written) {
    auto in = OIIO::ImageInput::open(temp.string());
    if (!in) return "it does not read back (" + OIIO::geterror() + ")";
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != written.width || spec.height != written.height || spec.nchannels != written.nchannels)
        return "it reads back as another image";
    const bool tiled = spec.tile_width > 0 && spec.tile_height > 0;
    const int rows = tiled ? spec.tile_height : 1, depth = std::max(1, spec.depth);
    std::vector<float> pixels;
    try {
        pixels.resize(size_t(spec.width) * rows * depth * spec.nchannels);
    } catch (const std::bad_alloc&) {
        return {};  // (too large to check here; close and fsync were checked)
    }
    const int last = spec.y + (spec.height - 1) / rows * rows;
    for (const int y0 : {spec.y, last}) {
        const int y1 = std::min(y0 + rows, spec.y + spec.height);
        const bool read = tiled ? in->read_tiles(0, 0, spec.x, spec.x + spec.width, y0, y1, spec.z, spec.z + depth, 0,
                                                 spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())
                                : in->read_scanlines(0, 0, y0, y1, spec.z, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                                                     pixels.data());
        if (!read) return "it does not read back (" + in->geterror() + ")";
    }
    return {};
}

std::string name_problem(const std::string& path) {
    const fs::path p(path);
    for (const fs::path& part : p)
        if (part.string().size() > NAME_MAX)
            return path.substr(0, 40) + "...: cannot write: a file or folder name of " +
                   std::to_string(part.string().size()) + " characters, beyond the file system's limit of " +
                   std::to_string(NAME_MAX) + " (NAME_MAX)";
    if (path.size() >= PATH_MAX - 32)
        return path.substr(0, 40) + "...: cannot write: a path of " + std::to_string(path.size()) +
               " characters, expected fewer than " + std::to_string(PATH_MAX - 32) + " (PATH_MAX " +
               std::to_string(PATH_MAX) + ", less room for the temporary beside it)";
    return {};
}

}  // namespace

void set_write_cancel_check(bool (*cancelled)()) { g_cancelled.store(cancelled); }

const char* temporary_being_written() { return g_temporary_set.load() ? g_temporary : nullptr; }

std::string output_name_problem(const std::string& path) { return name_problem(path); }

namespace {

// `image`'s spec as the file will hold it: `format`, else channel by channel as `channel_formats`
// where the writer allows (OpenEXR), else as the buffer holds them.
OIIO::ImageSpec file_spec(const OIIO::ImageBuf& image, const OIIO::ImageOutput& out, OIIO::TypeDesc format,
                          const std::vector<OIIO::TypeDesc>& channel_formats) {
    OIIO::ImageSpec spec = image.spec();
    if (format != OIIO::TypeUnknown) spec.set_format(format);
    if (!channel_formats.empty() && out.supports("channelformats")) {
        // the widest as the spec's format
        spec.channelformats = channel_formats;
        spec.format = *std::max_element(channel_formats.begin(), channel_formats.end(),
                                         [](OIIO::TypeDesc a, OIIO::TypeDesc b) { return a.size() < b.size(); });
    } else if (!channel_formats.empty() && format == OIIO::TypeUnknown) {
        spec.set_format(channel_formats.front());
    }
    if (!out.supports("tiles")) spec.tile_width = spec.tile_height = spec.tile_depth = 0;  // as ImageBuf::write
    return spec;
}

}  // namespace

Result<bool> write_image_atomically(const OIIO::ImageBuf& image, const std::string& path, OIIO::TypeDesc format,
                                    const std::vector<OIIO::TypeDesc>& channel_formats) {
    return write_parts_atomically({{&image, channel_formats}}, path, format);
}

Result<bool> write_parts_atomically(const std::vector<PartToWrite>& parts, const std::string& path,
                                    OIIO::TypeDesc format) {
    if (const std::string bad = name_problem(path); !bad.empty()) return Result<bool>::failure(bad);
    const fs::path temp = temporary_for(path);
    TemporaryMark mark(temp);
    auto cannot = [&](const std::string& why) { return discard(temp, path + ": cannot write: " + reason(why, temp)); };
    auto out = OIIO::ImageOutput::create(temp.string());
    if (!out) return cannot(OIIO::geterror());
    if (parts.size() > 1 && !out->supports("multiimage"))
        return cannot("a file of " + std::to_string(parts.size()) + " parts, and this format holds one");
    std::vector<OIIO::ImageSpec> specs;
    for (const PartToWrite& p : parts) specs.push_back(file_spec(*p.image, *out, format, p.channel_formats));
    if (!out->open(temp.string(), int(specs.size()), specs.data())) return cannot(out->geterror());
    for (size_t k = 0; k < parts.size(); ++k) {
        if (k > 0 && !out->open(temp.string(), specs[k], OIIO::ImageOutput::AppendSubimage))
            return cannot(out->geterror());
        // ImageBuf::write's own path, with every step's result checked, the close's too
        if (!parts[k].image->write(out.get())) {
            out->close();
            return cannot(parts[k].image->geterror().empty() ? out->geterror() : parts[k].image->geterror());
        }
    }
    if (!out->close()) return cannot(out->geterror());
    out.reset();
    if (const std::string why = sync_file(temp); !why.empty()) return cannot(why);
    if (const std::string why = read_back(temp, specs.front()); !why.empty())
        return cannot(why);
    return move_into_place(temp, path);
}

Result<bool> write_text_atomically(const std::string& text, const std::string& path) {
    if (const std::string bad = name_problem(path); !bad.empty()) return Result<bool>::failure(bad);
    const fs::path temp = temporary_for(path);
    TemporaryMark mark(temp);
    auto cannot = [&](const std::string& why) { return discard(temp, path + ": cannot write: " + reason(why, temp)); };
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) return cannot(std::strerror(errno));
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const std::string why = n < 0 ? std::strerror(errno) : "nothing written";
            ::close(fd);
            return cannot(why);
        }
        done += size_t(n);
    }
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        return cannot(why);
    }
    if (::close(fd) != 0) return cannot(std::strerror(errno));
    return move_into_place(temp, path);
}

}  // namespace wavecam
