// Uninitialised arrays for the large, short-lived buffers of acceleration-structure builds,
// and byte buffers for large files and textures. Arrays of 2 MiB or more are aligned to 2 MiB
// and advised to use transparent huge pages on Linux: a build touches every page once, and one
// fault per 2 MiB instead of per 4 KiB is the difference between a page-fault-bound and a
// compute-bound build (and, for a model's textures, most of their first touch:
// docs/performance.md, "Loading a model").
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace svetlo {

/// The size of a transparent huge page on x86-64 and on ARM64 with 4 KiB pages.
inline constexpr size_t kHugePageBytes = size_t{2} << 20;

/// Asks Linux to back the whole huge pages within [p, p + bytes) with transparent huge pages,
/// before they are first touched. Elsewhere, and where the kernel says no, nothing changes.
inline void advise_huge_pages(void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const auto at = reinterpret_cast<uintptr_t>(p);
    const uintptr_t begin = (at + kHugePageBytes - 1) & ~uintptr_t{kHugePageBytes - 1};
    const uintptr_t end = (at + bytes) & ~uintptr_t{kHugePageBytes - 1};
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

/// `n` zero bytes in a vector whose whole huge pages are advised as above: for a file read
/// whole and for a texture's decoded texels, each written once right after it is made.
inline std::vector<unsigned char> large_buffer(size_t n) {
    std::vector<unsigned char> buffer;
    buffer.reserve(n);  // allocated, not yet touched
    advise_huge_pages(buffer.data(), n);
    buffer.resize(n);
    return buffer;
}

template <class T>
class LargeArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

public:
    LargeArray() = default;
    /// `huge_pages`: false for an array written sparsely (room for a worst case), where every
    /// 2 MiB page touched would be cleared whole.
    explicit LargeArray(size_t count, bool huge_pages = true) : size_(count), capacity_(count) {
        if (count == 0) return;
        size_t bytes = count * sizeof(T);
        size_t align = bytes >= kHugePageBytes && huge_pages ? kHugePageBytes
                       : alignof(std::max_align_t) < 64      ? 64
                                                             : alignof(std::max_align_t);
        bytes = (bytes + align - 1) / align * align;
        void* p = std::aligned_alloc(align, bytes);
        if (!p) throw std::bad_alloc();
        if (align == kHugePageBytes) advise_huge_pages(p, bytes);
        data_.reset(static_cast<T*>(p));
    }

    /// Moved from, an array is empty and holds no memory (a later reuse() allocates).
    LargeArray(LargeArray&& other) noexcept
        : data_(std::move(other.data_)),
          size_(std::exchange(other.size_, 0)),
          capacity_(std::exchange(other.capacity_, 0)) {}
    LargeArray& operator=(LargeArray&& other) noexcept {
        data_ = std::move(other.data_);
        size_ = std::exchange(other.size_, 0);
        capacity_ = std::exchange(other.capacity_, 0);
        return *this;
    }

    T* data() { return data_.get(); }
    const T* data() const { return data_.get(); }
    T& operator[](size_t k) { return data_[k]; }
    const T& operator[](size_t k) const { return data_[k]; }
    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    /// Forgets the elements past `count` (their memory stays allocated).
    void truncate(size_t count) { size_ = count < size_ ? count : size_; }
    /// Holds `count` elements with unspecified values, keeping the memory when it is large
    /// enough (buffers reused frame after frame: no new pages to fault in).
    void reuse(size_t count) {
        if (count > capacity_) {
            *this = LargeArray(count);
        } else {
            size_ = count;
        }
    }
    T* begin() { return data(); }
    T* end() { return data() + size_; }
    const T* begin() const { return data(); }
    const T* end() const { return data() + size_; }

private:
    struct Free {
        void operator()(T* p) const { std::free(p); }
    };
    std::unique_ptr<T[], Free> data_;
    size_t size_ = 0;
    size_t capacity_ = 0;
};

}  // namespace svetlo
