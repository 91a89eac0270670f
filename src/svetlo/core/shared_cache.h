// What a command builds once and shares among its renders, by key: `svetlo compare` renders one
// scene under several techniques and a reference, `svetlo serve` renders it again at each
// slider's change and each step of a drag (docs/compare.md, "One scene, one BVH"). The ray
// tracers keep their geometry and BVH here (geometry/accel_cache.h), the rasterizer its
// triangle list (geometry/triangle_list_cache.h).
#pragma once

#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace svetlo {

/// The last `capacity` entries built, by key: equal keys, equal entries (the key names all that
/// an entry is made of). An entry is built in place and never moved, so it may refer to itself.
template <class T>
class SharedCache {
public:
    explicit SharedCache(size_t capacity = 4) : capacity_(capacity) {}

    /// The entry for `key`: made by `build` on the first request, then shared. Safe to call
    /// from several threads (one builds, the others wait).
    std::shared_ptr<const T> get(const std::string& key, const std::function<void(T&)>& build) {
        // Building under the lock keeps a second request for the same key from building it
        // again.
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = entries_.begin(); it != entries_.end(); ++it) {
            if (it->first != key) continue;
            entries_.splice(entries_.begin(), entries_, it);  // the most recently used first
            return entries_.front().second;
        }
        auto entry = std::make_shared<T>();
        build(*entry);
        ++builds_;
        entries_.emplace_front(key, entry);
        // An entry dropped here lives on in the renders that hold it.
        while (entries_.size() > capacity_) entries_.pop_back();
        return entry;
    }

    /// How many entries `get` has built (a hit builds none).
    int builds() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return builds_;
    }

private:
    size_t capacity_;
    mutable std::mutex mutex_;
    std::list<std::pair<std::string, std::shared_ptr<const T>>> entries_;  // newest first
    int builds_ = 0;
};

/// cache->get(key, build), or a new entry made by `build` where there is no cache or no key
/// (a scene read without one).
template <class T>
std::shared_ptr<const T> shared_entry(SharedCache<T>* cache, const std::string& key,
                                      const std::function<void(T&)>& build) {
    if (cache && !key.empty()) return cache->get(key, build);
    auto entry = std::make_shared<T>();
    build(*entry);
    return entry;
}

}  // namespace svetlo
