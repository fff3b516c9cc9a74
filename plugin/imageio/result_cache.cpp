#include "result_cache.h"

namespace wavecam::plugin {
namespace {
size_t pixel_bytes(const ResultCache::Image& image) { return image ? size_t(image->spec().image_bytes()) : 0; }
}  // namespace

ResultCache::Image ResultCache::find(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = used_.begin(); it != used_.end(); ++it)
        if (it->first == key) {
            used_.splice(used_.begin(), used_, it);
            return it->second;
        }
    return nullptr;
}

void ResultCache::insert(const std::string& key, Image image) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = used_.begin(); it != used_.end(); ++it)
        if (it->first == key) {
            bytes_ -= pixel_bytes(it->second);
            used_.erase(it);
            break;
        }
    bytes_ += pixel_bytes(image);
    used_.emplace_front(key, std::move(image));
    while (used_.size() > 1 && (used_.size() > max_entries_ || bytes_ > max_bytes_)) {
        bytes_ -= pixel_bytes(used_.back().second);
        used_.pop_back();
    }
}

size_t ResultCache::entries() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return used_.size();
}

size_t ResultCache::bytes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return bytes_;
}

}  // namespace wavecam::plugin
