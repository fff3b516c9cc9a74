#include "summation/kernel/basis_spectra.h"

namespace wavecam::detail {
namespace {

constexpr int L = BasisSpectra::kLanes;
// Chunks ahead that a chunk's pass asks the memory for.
constexpr int kAhead = 4;

// Modes [m0, m0 + G) of one chunk: G sums of L lanes kept in registers over the basis.
template <int G>
__attribute__((always_inline)) inline void mix_modes(const float* image, size_t plane, int rank, int modes,
                                                     const float* spectra, int m0, float* total) {
    float re[G][L] = {}, im[G][L] = {};
    for (int r = 0; r < rank; ++r) {
        const float* x = image + 2 * plane * r;
        // (the planes are far apart, one stream each: more than the processor's prefetcher follows)
        __builtin_prefetch(x + 2 * L * kAhead);
        float xr[L], xi[L];
        for (int l = 0; l < L; ++l) {
            xr[l] = x[2 * l];
            xi[l] = x[2 * l + 1];
        }
        const float* s = spectra + (size_t(r) * modes + m0) * 2 * L;
        for (int g = 0; g < G; ++g)
            for (int l = 0; l < L; ++l) {
                const float sr = s[2 * L * g + l], si = s[2 * L * g + L + l];
                re[g][l] += xr[l] * sr - xi[l] * si;
                im[g][l] += xr[l] * si + xi[l] * sr;
            }
    }
    for (int g = 0; g < G; ++g) {
        float* t = total + 2 * plane * (m0 + g);
        __builtin_prefetch(t + 2 * L * kAhead, 1);
        for (int l = 0; l < L; ++l) {
            t[2 * l] = re[g][l];
            t[2 * l + 1] = im[g][l];
        }
    }
}

// (built for AVX2 too, chosen when the processor has it: the same multiplies and adds, wider)
__attribute__((target_clones("avx2", "default"))) void mix_chunk(const float* image, size_t plane, int rank,
                                                                  int modes, const float* spectra, float* total) {
    int m0 = 0;
    for (; m0 + 4 <= modes; m0 += 4) mix_modes<4>(image, plane, rank, modes, spectra, m0, total);
    for (; m0 + 2 <= modes; m0 += 2) mix_modes<2>(image, plane, rank, modes, spectra, m0, total);
    for (; m0 < modes; ++m0) mix_modes<1>(image, plane, rank, modes, spectra, m0, total);
}

}  // namespace

BasisSpectra::BasisSpectra(int rank, int modes, size_t points)
    : rank_(rank),
      modes_(modes),
      points_(points),
      chunks_((points + L - 1) / L),
      values_(chunks_ * size_t(rank) * modes * 2 * L, 0.0f) {}

void BasisSpectra::set(int r, int m, const std::complex<float>* spectrum) {
    for (size_t q = 0; q < points_; ++q) {
        float* v = values_.data() + (((q / L) * rank_ + r) * modes_ + m) * 2 * L + q % L;
        v[0] = spectrum[q].real();
        v[L] = spectrum[q].imag();
    }
}

void BasisSpectra::mix(size_t chunk, const std::complex<float>* image, std::complex<float>* total) const {
    const size_t at = chunk * L;
    mix_chunk(reinterpret_cast<const float*>(image + at), plane(), rank_, modes_,
              values_.data() + chunk * size_t(rank_) * modes_ * 2 * L, reinterpret_cast<float*>(total + at));
}

}  // namespace wavecam::detail
