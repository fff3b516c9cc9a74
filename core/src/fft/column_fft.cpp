#include "fft/column_fft.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "base/parallel.h"

namespace wavecam::detail {
namespace {

// A complex value as two floats, with the arithmetic spelt out (std::complex's product checks
// for infinities and does not vectorise).
struct Cf {
    float re, im;
};
inline Cf operator+(Cf a, Cf b) { return {a.re + b.re, a.im + b.im}; }
inline Cf operator-(Cf a, Cf b) { return {a.re - b.re, a.im - b.im}; }
inline Cf operator*(Cf a, Cf b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline Cf operator*(float s, Cf a) { return {s * a.re, s * a.im}; }
// a times -i (forward) or +i (inverse): sign = -1 or +1
inline Cf times_i(Cf a, float sign) { return {-sign * a.im, sign * a.re}; }

// One stage's butterflies for p in [0, m), lanes [j0, j1) of each row; rows are `row` values
// apart, input row p + j m, output row P p + k. Input and output never overlap (ivdep on the
// lanes' loops: they vectorise).
struct StageArgs {
    const Cf* x;
    Cf* y;
    const Cf* twiddle;
    int m;
    size_t row, j0, j1;
    float sign;  // -1 forward, +1 inverse
};

__attribute__((target_clones("avx2", "default"))) void radix2(const StageArgs& a) {
    for (int p = 0; p < a.m; ++p) {
        const Cf w = a.twiddle[p];
        const Cf *x0 = a.x + size_t(p) * a.row, *x1 = x0 + size_t(a.m) * a.row;
        Cf *y0 = a.y + size_t(2 * p) * a.row, *y1 = y0 + a.row;
#pragma GCC ivdep
        for (size_t j = a.j0; j < a.j1; ++j) {
            const Cf u = x0[j], v = x1[j];
            y0[j] = u + v;
            y1[j] = (u - v) * w;
        }
    }
}

__attribute__((target_clones("avx2", "default"))) void radix3(const StageArgs& a) {
    const float h = a.sign * float(std::sqrt(3.0) / 2);  // sin of the third turn, signed
    for (int p = 0; p < a.m; ++p) {
        const Cf w1 = a.twiddle[2 * p], w2 = a.twiddle[2 * p + 1];
        const Cf* x0 = a.x + size_t(p) * a.row;
        const Cf *x1 = x0 + size_t(a.m) * a.row, *x2 = x1 + size_t(a.m) * a.row;
        Cf* y0 = a.y + size_t(3 * p) * a.row;
        Cf *y1 = y0 + a.row, *y2 = y1 + a.row;
#pragma GCC ivdep
        for (size_t j = a.j0; j < a.j1; ++j) {
            const Cf u = x0[j], s = x1[j] + x2[j], d = x1[j] - x2[j];
            const Cf c = u - 0.5f * s, r = {-h * d.im, h * d.re};  // r = (+-i) sqrt(3)/2 d
            y0[j] = u + s;
            y1[j] = (c + r) * w1;
            y2[j] = (c - r) * w2;
        }
    }
}

__attribute__((target_clones("avx2", "default"))) void radix4(const StageArgs& a) {
    for (int p = 0; p < a.m; ++p) {
        const Cf w1 = a.twiddle[3 * p], w2 = a.twiddle[3 * p + 1], w3 = a.twiddle[3 * p + 2];
        const size_t step = size_t(a.m) * a.row;
        const Cf* x0 = a.x + size_t(p) * a.row;
        Cf* y0 = a.y + size_t(4 * p) * a.row;
#pragma GCC ivdep
        for (size_t j = a.j0; j < a.j1; ++j) {
            const Cf u0 = x0[j], u1 = x0[j + step], u2 = x0[j + 2 * step], u3 = x0[j + 3 * step];
            const Cf b0 = u0 + u2, b1 = u0 - u2, b2 = u1 + u3, b3 = times_i(u1 - u3, a.sign);
            y0[j] = b0 + b2;
            y0[j + a.row] = (b1 + b3) * w1;
            y0[j + 2 * a.row] = (b0 - b2) * w2;
            y0[j + 3 * a.row] = (b1 - b3) * w3;
        }
    }
}

__attribute__((target_clones("avx2", "default"))) void radix5(const StageArgs& a) {
    const float c1 = float(std::cos(2 * M_PI / 5)), c2 = float(std::cos(4 * M_PI / 5));
    const float s1 = a.sign * float(std::sin(2 * M_PI / 5)), s2 = a.sign * float(std::sin(4 * M_PI / 5));
    for (int p = 0; p < a.m; ++p) {
        const Cf* w = a.twiddle + 4 * size_t(p);
        const size_t step = size_t(a.m) * a.row;
        const Cf* x0 = a.x + size_t(p) * a.row;
        Cf* y0 = a.y + size_t(5 * p) * a.row;
#pragma GCC ivdep
        for (size_t j = a.j0; j < a.j1; ++j) {
            const Cf u0 = x0[j], u1 = x0[j + step], u2 = x0[j + 2 * step], u3 = x0[j + 3 * step],
                     u4 = x0[j + 4 * step];
            const Cf t1 = u1 + u4, t2 = u2 + u3, t3 = u1 - u4, t4 = u2 - u3;
            const Cf e1 = u0 + c1 * t1 + c2 * t2, e2 = u0 + c2 * t1 + c1 * t2;
            // (+-i) times the odd parts: X1,4 = e1 +- i (s1 t3 + s2 t4), X2,3 = e2 +- i (s2 t3 - s1 t4)
            const Cf o1 = s1 * t3 + s2 * t4, o2 = s2 * t3 - s1 * t4;
            const Cf r1 = {-o1.im, o1.re}, r2 = {-o2.im, o2.re};
            y0[j] = u0 + t1 + t2;
            y0[j + a.row] = (e1 + r1) * w[0];
            y0[j + 2 * a.row] = (e2 + r2) * w[1];
            y0[j + 3 * a.row] = (e2 - r2) * w[2];
            y0[j + 4 * a.row] = (e1 - r1) * w[3];
        }
    }
}

}  // namespace

ColumnFft::ColumnFft(int length, bool inverse) : n_(length), inverse_(inverse) {
    int rest = length;
    double sign = inverse ? 1.0 : -1.0;
    while (rest > 1) {
        int radix = 0;
        for (int p : {4, 2, 3, 5})
            if (rest % p == 0) {
                radix = p;
                break;
            }
        if (radix == 0) {
            ok_ = false;
            return;
        }
        // this stage's length is `rest` = radix m: twiddles w_rest^(p k)
        Stage s{radix, rest / radix, {}};
        s.twiddle.resize(size_t(s.m) * (radix - 1));
        for (int p = 0; p < s.m; ++p)
            for (int k = 1; k < radix; ++k) {
                const double angle = sign * 2 * M_PI * double(p) * k / rest;
                s.twiddle[size_t(p) * (radix - 1) + k - 1] = {float(std::cos(angle)), float(std::sin(angle))};
            }
        stages_.push_back(std::move(s));
        rest /= radix;
    }
}

void ColumnFft::transform(std::complex<float>* data, std::complex<float>* work, int columns, int first, int last,
                          int threads) const {
    // (a row's run copied as bytes: the element loop compiled to one scalar float at a time)
    if (transform_where(data, work, columns, first, last, threads) != data)
        for (int r = 0; r < n_; ++r)
            std::memcpy(data + size_t(r) * columns + first, work + size_t(r) * columns + first,
                        sizeof(std::complex<float>) * size_t(last - first));
}

std::complex<float>* ColumnFft::transform_where(std::complex<float>* data, std::complex<float>* work, int columns,
                                                int first, int last, int threads,
                                                const std::complex<float>* source) const {
    // On one thread, a run of columns too wide for the cache goes a block at a time: a block's
    // rows (data and work) stay in the cache through all of its stages, where the whole run
    // would stream from memory once a stage. Columns are independent: the same values.
    const int block = block_columns(n_);
    if (threads <= 1 && last - first > block) {
        for (int c0 = first; c0 < last; c0 += block)
            stages(data, work, columns, c0, std::min(last, c0 + block), 1, source);
        return ends_in_work() ? work : data;
    }
    return stages(data, work, columns, first, last, threads, source);
}

int ColumnFft::block_columns(int length) {
    return std::max(kMinBlockColumns, int(kCacheBytes / (2 * sizeof(std::complex<float>) * size_t(length))) & ~7);
}

std::complex<float>* ColumnFft::stages(std::complex<float>* data, std::complex<float>* work, int columns, int first,
                                       int last, int threads, const std::complex<float>* source) const {
    Cf *x = reinterpret_cast<Cf*>(data), *y = reinterpret_cast<Cf*>(work);
    // the first stage's input: `source` where given (x is then only written, from the second stage)
    const Cf* input = source ? reinterpret_cast<const Cf*>(source) : x;
    if (stages_.empty() && source)  // (a length of 1: the transform is the identity)
        for (int r = 0; r < n_; ++r)
            std::copy(input + size_t(r) * columns + first, input + size_t(r) * columns + last, x + size_t(r) * columns + first);
    const bool whole = first == 0 && last == columns;
    size_t stride = 1;  // s: the sub-sequences split off so far
    for (const Stage& st : stages_) {
        const StageArgs stage{stride == 1 ? input : x, y, reinterpret_cast<const Cf*>(st.twiddle.data()), st.m,
                              stride * columns, 0, 0, inverse_ ? 1.0f : -1.0f};
        // sub-sequence q's lanes are [q columns + first, q columns + last): one run where every
        // column is asked for; each run's lanes split into `threads` parts (a stage's lanes are
        // independent: each reads and writes its own)
        const long runs = whole ? 1 : long(stride), parts = std::max(1, threads);
        auto run = [&](long task) {
            const size_t q = size_t(task / parts), part = size_t(task % parts);
            const size_t j0 = whole ? 0 : q * columns + first, j1 = whole ? stride * columns : q * columns + last;
            StageArgs a = stage;
            a.j0 = j0 + (j1 - j0) * part / parts;
            a.j1 = j0 + (j1 - j0) * (part + 1) / parts;
            switch (st.radix) {
                case 2: radix2(a); break;
                case 3: radix3(a); break;
                case 4: radix4(a); break;
                default: radix5(a); break;
            }
        };
        if (parts > 1) {
            parallel_for(0, runs * parts, threads, run);
        } else {  // (no parallel construct at all: the kernel summation takes thousands of small transforms)
            for (long task = 0; task < runs; ++task) run(task);
        }
        std::swap(x, y);
        stride *= st.radix;
    }
    return reinterpret_cast<std::complex<float>*>(x);
}

}  // namespace wavecam::detail
