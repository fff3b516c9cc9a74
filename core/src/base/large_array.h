// Memory for large arrays that are written in full before they are read (the convolution's
// kernel spectra): not zero-filled first (a vector's resize writes every byte once before the
// work writes it again), and on huge pages where the kernel offers them (one fault a 2 MiB page
// instead of 512 for 4 KiB pages; page faults were a fifth of a 1080p frame's time). Internal to core.
#pragma once
#include <sys/mman.h>

#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace wavecam::detail {

template <class T>
class LargeArray {
    static_assert(std::is_trivially_destructible_v<T>, "a LargeArray holds plain values");

public:
    LargeArray() = default;
    // n values, their contents undefined until written; throws std::bad_alloc as a vector does
    explicit LargeArray(size_t n) : n_(n) {
        if (n == 0) return;
        constexpr size_t kHugePage = size_t(2) << 20;
        const size_t bytes = (n * sizeof(T) + kHugePage - 1) / kHugePage * kHugePage;
        void* p = std::aligned_alloc(kHugePage, bytes);
        if (!p) throw std::bad_alloc();
        ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: without huge pages the array still works
        p_.reset(static_cast<T*>(p));
    }

    T* data() const { return p_.get(); }
    size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    T& operator[](size_t k) const { return p_[k]; }

private:
    struct Free {
        void operator()(T* p) const { std::free(p); }
    };
    std::unique_ptr<T[], Free> p_;
    size_t n_ = 0;
};

}  // namespace wavecam::detail
