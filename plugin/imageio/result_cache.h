// The plugin's computed images, by request key: oiiotool opens one input several times per
// command, and each open after the first takes the image already made. Bounded: at most
// `max_entries` images and `max_bytes` of pixels, the least recently used dropped first; the
// newest is always kept, whatever its size (a frame larger than the budget is still opened
// several times, and computing it again would cost far more than holding it).
#pragma once
#include <OpenImageIO/imagebuf.h>

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace wavecam::plugin {

class ResultCache {
public:
    using Image = std::shared_ptr<const OIIO::ImageBuf>;

    ResultCache(size_t max_entries, size_t max_bytes) : max_entries_(max_entries), max_bytes_(max_bytes) {}

    // The image kept under `key` (now the most recently used), or null.
    Image find(const std::string& key);

    // Keeps `image` under `key` as the most recently used, replacing what was there, and drops
    // the least recently used others while over either bound.
    void insert(const std::string& key, Image image);

    size_t entries() const;
    size_t bytes() const;  // pixel bytes held (ImageSpec::image_bytes of each)

private:
    const size_t max_entries_, max_bytes_;
    mutable std::mutex mutex_;
    std::list<std::pair<std::string, Image>> used_;  // most recently used first
    size_t bytes_ = 0;
};

}  // namespace wavecam::plugin
