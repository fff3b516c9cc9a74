// Complex 2D FFTs of one rectangular size through kissfft (BSD-3-Clause; see docs/install.md):
// complex 1D transforms along the rows, then along the columns, rows and columns spread over
// threads (kissfft's configurations are read-only during a transform). Internal to core.
#pragma once
#include <kiss_fft.h>
#include <omp.h>

#include <complex>
#include <vector>

namespace wavecam::detail {

class ComplexFft2D {
public:
    ComplexFft2D(int width, int height, int nthreads)
        : w_(width),
          h_(height),
          threads_(nthreads),
          row_forward_(kiss_fft_alloc(width, 0, nullptr, nullptr)),
          row_inverse_(kiss_fft_alloc(width, 1, nullptr, nullptr)),
          column_forward_(kiss_fft_alloc(height, 0, nullptr, nullptr)),
          column_inverse_(kiss_fft_alloc(height, 1, nullptr, nullptr)) {}
    ~ComplexFft2D() {
        kiss_fft_free(row_forward_);
        kiss_fft_free(row_inverse_);
        kiss_fft_free(column_forward_);
        kiss_fft_free(column_inverse_);
    }
    ComplexFft2D(const ComplexFft2D&) = delete;
    ComplexFft2D& operator=(const ComplexFft2D&) = delete;

    bool ok() const { return row_forward_ && row_inverse_ && column_forward_ && column_inverse_; }
    int width() const { return w_; }
    int height() const { return h_; }
    size_t size() const { return size_t(w_) * h_; }

    // In place, height x width row-major. Rows at or beyond `rows` are known to be zero (their
    // transforms are skipped). The inverse is scaled by width x height (kissfft does not normalise).
    void forward(std::complex<float>* data, int rows = -1) const { transform(data, rows, row_forward_, column_forward_); }
    void inverse(std::complex<float>* data) const { transform(data, -1, row_inverse_, column_inverse_); }

    // Transforms of fewer points run on one thread.
    static constexpr size_t kParallelPoints = 1 << 16;

private:
    static kiss_fft_cpx* cpx(std::complex<float>* p) { return reinterpret_cast<kiss_fft_cpx*>(p); }

    void transform(std::complex<float>* data, int rows, kiss_fft_cfg row_cfg, kiss_fft_cfg column_cfg) const {
        const int busy = rows < 0 ? h_ : std::min(rows, h_);
        // (small transforms on one thread: a parallel region per transform costs more than it
        // saves, and far more where other processes share the cores)
#pragma omp parallel num_threads(threads_) if (size() >= kParallelPoints)
        {
            std::vector<std::complex<float>> in(size_t(std::max(w_, h_)) * kColumns), out(std::max(w_, h_));
#pragma omp for schedule(static)
            for (int r = 0; r < busy; ++r) {
                std::complex<float>* row = data + size_t(r) * w_;
                std::copy(row, row + w_, in.begin());
                kiss_fft(row_cfg, cpx(in.data()), cpx(row));
            }
            // columns kColumns at a time: each row's run of them is read and written whole
#pragma omp for schedule(static)
            for (int k0 = 0; k0 < w_; k0 += kColumns) {
                const int n = std::min(kColumns, w_ - k0);
                for (int r = 0; r < h_; ++r)
                    for (int c = 0; c < n; ++c) in[size_t(c) * h_ + r] = data[size_t(r) * w_ + k0 + c];
                for (int c = 0; c < n; ++c) {
                    kiss_fft(column_cfg, cpx(in.data() + size_t(c) * h_), cpx(out.data()));
                    std::copy(out.begin(), out.begin() + h_, in.begin() + size_t(c) * h_);
                }
                for (int r = 0; r < h_; ++r)
                    for (int c = 0; c < n; ++c) data[size_t(r) * w_ + k0 + c] = in[size_t(c) * h_ + r];
            }
        }
    }

    static constexpr int kColumns = 8;
    int w_, h_, threads_;
    kiss_fft_cfg row_forward_, row_inverse_, column_forward_, column_inverse_;
};

}  // namespace wavecam::detail
