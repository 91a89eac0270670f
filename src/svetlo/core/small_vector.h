// A vector that keeps its first N elements inline (no allocation) and moves to the heap only
// beyond them: for per-ray scratch lists in hot paths (CSG span lists).
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

namespace svetlo {

template <class T, size_t N>
class SmallVector {
    static_assert(std::is_trivially_copyable_v<T>);

public:
    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    void clear() {
        size_ = 0;
        heap_.clear();
    }
    void push_back(const T& v) {
        if (size_ < N) {
            inline_[size_] = v;
        } else {
            if (size_ == N) heap_.assign(inline_, inline_ + N);
            heap_.push_back(v);
        }
        ++size_;
    }
    void pop_back() {
        if (size_ > N) {
            heap_.pop_back();
            if (size_ - 1 == N) {  // back to the inline storage
                for (size_t k = 0; k < N; ++k) inline_[k] = heap_[k];
                heap_.clear();
            }
        }
        --size_;
    }
    T& operator[](size_t k) { return size_ <= N ? inline_[k] : heap_[k]; }
    const T& operator[](size_t k) const { return size_ <= N ? inline_[k] : heap_[k]; }
    T& back() { return (*this)[size_ - 1]; }

private:
    T inline_[N];
    std::vector<T> heap_;  // all elements once there are more than N
    size_t size_ = 0;
};

}  // namespace svetlo
