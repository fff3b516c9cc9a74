// Memory for large arrays (the convolution's kernels, their spectra, a tile's transform arrays):
// pages of their own, mapped on allocation and unmapped on release, so that what a finished
// stage frees goes back to the system at once (from the allocator's heap, a 4K frame's freed
// kernels stayed in the process and raised its peak); zero until written, as the kernel hands
// out fresh pages, with no pass that writes the zeros first (a vector's resize wrote every byte
// once before the work wrote it again). Huge pages (2 MiB) only where asked and the array is
// large: a transform striding across tens of MB misses the TLB on small pages, but a huge page
// costs its whole 2 MiB of zeroing at the first touch, and on virtual machines that hand free
// memory back to their host every fresh huge page is new to the host too (a 1080p frame at 50deg
// spent a quarter of its CPU time zeroing huge pages; on small pages 0.85x its time). Internal to core.
#pragma once
#include <sys/mman.h>

#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>

namespace wavecam::detail {

enum class Pages { small, huge_if_large };

template <class T>
class LargeArray {
    static_assert(std::is_trivially_destructible_v<T> && std::is_trivially_copyable_v<T>, "a LargeArray holds plain values");

public:
    LargeArray() = default;
    // n values, each zero until written; throws std::bad_alloc as a vector does
    explicit LargeArray(size_t n, Pages pages = Pages::small) : n_(n) {
        if (n == 0) return;
        constexpr size_t kHugePage = size_t(2) << 20, kSmallPage = size_t(4) << 10;
        constexpr size_t kHugeFrom = size_t(16) << 20;  // beyond the TLB's reach on small pages
        const bool huge = pages == Pages::huge_if_large && n * sizeof(T) >= kHugeFrom;
        const size_t page = huge ? kHugePage : kSmallPage;
        const size_t bytes = (n * sizeof(T) + page - 1) / page * page;
        // on huge pages, a huge page more than asked, so that the array can start on a huge
        // page's boundary
        const size_t extra = huge ? kHugePage : 0;
        void* raw = ::mmap(nullptr, bytes + extra, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        uintptr_t first = reinterpret_cast<uintptr_t>(raw);
        if (huge) {
            first = (first + kHugePage - 1) / kHugePage * kHugePage;
            const size_t head = first - reinterpret_cast<uintptr_t>(raw);
            if (head > 0) ::munmap(raw, head);
            if (kHugePage - head > 0) ::munmap(reinterpret_cast<void*>(first + bytes), kHugePage - head);
            ::madvise(reinterpret_cast<void*>(first), bytes, MADV_HUGEPAGE);  // advice only: the array works without
        }
        p_ = std::unique_ptr<T[], Unmap>(reinterpret_cast<T*>(first), Unmap{bytes});
    }

    T* data() const { return p_.get(); }
    size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    T& operator[](size_t k) const { return p_[k]; }

private:
    struct Unmap {
        size_t bytes = 0;
        void operator()(T* p) const { ::munmap(p, bytes); }
    };
    std::unique_ptr<T[], Unmap> p_;
    size_t n_ = 0;
};

}  // namespace wavecam::detail
