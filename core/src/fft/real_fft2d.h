// Real 2D FFTs of one size (width x height) through kissfft (BSD-3-Clause; see docs/install.md on why not FFTW):
// real 1D transforms along rows, complex 1D transforms along the n/2 + 1 columns.
// (Debian's kissfft 131 returns no configuration from kiss_fftndr_alloc, so the 2D transform
// is composed here from the 1D ones.) Internal to core; one object per thread.
#pragma once
#include <kiss_fft.h>
#include <kiss_fftr.h>

#include <algorithm>
#include <complex>
#include <vector>

#include "fft/column_fft.h"  // fft_friendly_size

namespace wavecam::detail {

class RealFft2D {
public:
    RealFft2D(int width, int height)
        : width_(width),
          height_(height),
          half_(width / 2 + 1),
          row_forward_(kiss_fftr_alloc(width, 0, nullptr, nullptr)),
          row_inverse_(kiss_fftr_alloc(width, 1, nullptr, nullptr)),
          column_forward_(kiss_fft_alloc(height, 0, nullptr, nullptr)),
          column_inverse_(kiss_fft_alloc(height, 1, nullptr, nullptr)),
          column_(height),
          column_out_(height) {}
    ~RealFft2D() {
        kiss_fftr_free(row_forward_);
        kiss_fftr_free(row_inverse_);
        kiss_fft_free(column_forward_);
        kiss_fft_free(column_inverse_);
    }
    RealFft2D(const RealFft2D&) = delete;
    RealFft2D& operator=(const RealFft2D&) = delete;

    bool ok() const { return row_forward_ && row_inverse_ && column_forward_ && column_inverse_; }
    size_t spectrum_size() const { return size_t(height_) * half_; }

    // height x width real (row-major) -> height x (width/2 + 1) spectrum (row-major). Rows
    // [zero_begin, zero_end) are known to be zero (a tile's padding, a wrapped kernel's middle):
    // their transforms are skipped.
    void forward(const float* image, std::complex<float>* spectrum, int zero_begin = 0, int zero_end = 0) {
        for (int r = 0; r < height_; ++r)
            if (r >= zero_begin && r < zero_end)
                std::fill(spectrum + size_t(r) * half_, spectrum + size_t(r + 1) * half_, std::complex<float>(0));
            else
                kiss_fftr(row_forward_, image + size_t(r) * width_, cpx(spectrum + size_t(r) * half_));
        columns(spectrum, column_forward_);
    }
    // spectrum -> height x width real, scaled by width x height (kissfft does not normalise); the
    // spectrum is overwritten
    void inverse(std::complex<float>* spectrum, float* image) {
        columns(spectrum, column_inverse_);
        for (int r = 0; r < height_; ++r)
            kiss_fftri(row_inverse_, cpx(spectrum + size_t(r) * half_), image + size_t(r) * width_);
    }

private:
    static kiss_fft_cpx* cpx(std::complex<float>* p) { return reinterpret_cast<kiss_fft_cpx*>(p); }

    void columns(std::complex<float>* spectrum, kiss_fft_cfg cfg) {
        for (int k = 0; k < half_; ++k) {
            for (int r = 0; r < height_; ++r) column_[r] = spectrum[size_t(r) * half_ + k];
            kiss_fft(cfg, cpx(column_.data()), cpx(column_out_.data()));
            for (int r = 0; r < height_; ++r) spectrum[size_t(r) * half_ + k] = column_out_[r];
        }
    }

    int width_, height_, half_;
    kiss_fftr_cfg row_forward_, row_inverse_;
    kiss_fft_cfg column_forward_, column_inverse_;
    std::vector<std::complex<float>> column_, column_out_;
};

}  // namespace wavecam::detail
