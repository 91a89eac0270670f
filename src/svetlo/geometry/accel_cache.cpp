#include "svetlo/geometry/accel_cache.h"

namespace svetlo {

std::shared_ptr<const BuiltGeometry> AccelCache::get(
    const std::string& key, const std::function<void(BuiltGeometry&)>& build) {
    // Building under the lock keeps a second request for the same key from building it
    // again; the commands that share a cache render one job after the other.
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
        if (it->first != key) continue;
        entries_.splice(entries_.begin(), entries_, it);  // the most recently used first
        return entries_.front().second;
    }
    auto entry = std::make_shared<BuiltGeometry>();
    build(*entry);
    ++builds_;
    entries_.emplace_front(key, entry);
    // An entry dropped here lives on in the renders that hold it.
    while (entries_.size() > capacity_) entries_.pop_back();
    return entry;
}

int AccelCache::builds() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return builds_;
}

std::shared_ptr<const BuiltGeometry> built_geometry(
    AccelCache* cache, const std::string& key, const std::function<void(BuiltGeometry&)>& build) {
    if (cache) return cache->get(key, build);
    auto entry = std::make_shared<BuiltGeometry>();
    build(*entry);
    return entry;
}

}  // namespace svetlo
