// fft.cpp - the radix-2 transform of fft.hpp, two stages a pass: every pass runs along the
// columns of a row-major array, one row of values at a time, so the
// innermost loop is a plain loop over contiguous doubles that the compiler
// vectorises; the other axis goes through a transposed copy.
#include "dsp/fft.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "common/error.hpp"

namespace vqtex::dsp {
namespace {

bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// The butterflies are built for the widest vectors the CPU has (rounding
// may differ between the builds; the callers' margin covers every one).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(VQTEX_NO_TARGET_CLONES)
#define VQTEX_FFT_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define VQTEX_FFT_CLONES
#endif

// One butterfly on n columns: a + w b and a - w b, w = wr + i wi.
VQTEX_FFT_CLONES
void butterflies(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi,
                 double wr, double wi, int n) {
    for (int x = 0; x < n; ++x) {
        const double tr = br[x] * wr - bi[x] * wi, ti = br[x] * wi + bi[x] * wr;
        br[x] = ar[x] - tr;
        bi[x] = ai[x] - ti;
        ar[x] += tr;
        ai[x] += ti;
    }
}

// Two stages at once on n columns (radix 2 squared): with a, b, c, d the
// rows j, j + L/2, j + L and j + 3L/2 of a group of 2L, the stage of L
// pairs (a, b) and (c, d) with twiddle w1, the stage of 2L then (a, c)
// with w2 and (b, d) with w3: the same arithmetic as the two stages one
// after the other, in one pass over memory.
VQTEX_FFT_CLONES
void butterflies4(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi,
                  double* __restrict cr, double* __restrict ci, double* __restrict dr, double* __restrict di,
                  double w1r, double w1i, double w2r, double w2i, double w3r, double w3i, int n) {
    for (int x = 0; x < n; ++x) {
        const double tr = br[x] * w1r - bi[x] * w1i, ti = br[x] * w1i + bi[x] * w1r;
        const double ur = dr[x] * w1r - di[x] * w1i, ui = dr[x] * w1i + di[x] * w1r;
        const double a1r = ar[x] + tr, a1i = ai[x] + ti, b1r = ar[x] - tr, b1i = ai[x] - ti;
        const double c1r = cr[x] + ur, c1i = ci[x] + ui, d1r = cr[x] - ur, d1i = ci[x] - ui;
        const double vr = c1r * w2r - c1i * w2i, vi = c1r * w2i + c1i * w2r;
        const double zr = d1r * w3r - d1i * w3i, zi = d1r * w3i + d1i * w3r;
        ar[x] = a1r + vr;
        ai[x] = a1i + vi;
        cr[x] = a1r - vr;
        ci[x] = a1i - vi;
        br[x] = b1r + zr;
        bi[x] = b1i + zi;
        dr[x] = b1r - zr;
        di[x] = b1i - zi;
    }
}

}  // namespace

Fft2d::Fft2d(int width, int height) : w_(width), h_(height) {
    if (!power_of_two(width) || !power_of_two(height))
        fail(VQTEX_ERROR_INTERNAL, "a transform's sides must be powers of two");
    n_ = std::max(width, height);
    cos_.resize(std::size_t(n_ / 2 + 1));
    sin_.resize(std::size_t(n_ / 2 + 1));
    const double tau = 6.283185307179586476925286766559;
    for (int k = 0; k <= n_ / 2; ++k) {
        cos_[std::size_t(k)] = std::cos(tau * k / n_);
        sin_[std::size_t(k)] = std::sin(tau * k / n_);
    }
}

void Fft2d::columns(double* re, double* im, int rows, int cols, int stride, int sign) const {
    const auto row_re = [&](int r) { return re + std::size_t(r) * std::size_t(stride); };
    const auto row_im = [&](int r) { return im + std::size_t(r) * std::size_t(stride); };
    // Rows in bit-reversed order, then the butterflies in place.
    for (int i = 1, j = 0; i < rows; ++i) {
        int bit = rows >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j)
            for (int x = 0; x < cols; ++x) {
                std::swap(row_re(i)[x], row_re(j)[x]);
                std::swap(row_im(i)[x], row_im(j)[x]);
            }
    }
    // The stages of L and 2L two at a time, then the last one alone when
    // their count is odd. The twiddles come from the same table either way.
    const auto twiddle = [&](int k, double& wr, double& wi) {
        wr = cos_[std::size_t(k)];
        wi = sign * sin_[std::size_t(k)];
    };
    int len = 2;
    for (; 2 * len <= rows; len <<= 2) {
        const int half = len / 2, step = n_ / len, step2 = n_ / (2 * len);
        for (int j = 0; j < half; ++j) {
            double w1r, w1i, w2r, w2i, w3r, w3i;
            twiddle(j * step, w1r, w1i);
            twiddle(j * step2, w2r, w2i);
            twiddle((j + half) * step2, w3r, w3i);
            for (int base = 0; base < rows; base += 2 * len)
                butterflies4(row_re(base + j), row_im(base + j), row_re(base + j + half), row_im(base + j + half),
                             row_re(base + j + len), row_im(base + j + len), row_re(base + j + len + half),
                             row_im(base + j + len + half), w1r, w1i, w2r, w2i, w3r, w3i, cols);
        }
    }
    if (len <= rows) {
        const int half = len / 2, step = n_ / len;
        for (int j = 0; j < half; ++j) {
            double wr, wi;
            twiddle(j * step, wr, wi);
            for (int base = 0; base < rows; base += len)
                butterflies(row_re(base + j), row_im(base + j), row_re(base + j + half), row_im(base + j + half), wr,
                            wi, cols);
        }
    }
}

namespace {

// dst (cols rows of stride dst_stride) = the transpose of src (rows rows of
// stride src_stride), by tiles that stay in the cache.
void transpose(const double* src, int rows, int cols, int src_stride, double* dst, int dst_stride) {
    constexpr int kTile = 16;
    for (int y0 = 0; y0 < rows; y0 += kTile)
        for (int x0 = 0; x0 < cols; x0 += kTile) {
            const int y1 = std::min(rows, y0 + kTile), x1 = std::min(cols, x0 + kTile);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    dst[std::size_t(x) * std::size_t(dst_stride) + std::size_t(y)] =
                        src[std::size_t(y) * std::size_t(src_stride) + std::size_t(x)];
        }
}

}  // namespace

void Fft2d::rows(double* re, double* im, int count, int sign, FftScratch& scratch) const {
    const std::size_t n = std::size_t(w_) * std::size_t(count);
    if (scratch.re.size() < n) {
        scratch.re.resize(n);
        scratch.im.resize(n);
    }
    double* tre = scratch.re.data();
    double* tim = scratch.im.data();
    transpose(re, count, w_, w_, tre, count);
    transpose(im, count, w_, w_, tim, count);
    columns(tre, tim, w_, count, count, sign);
    transpose(tre, w_, count, count, re, w_);
    transpose(tim, w_, count, count, im, w_);
}

void Fft2d::forward(double* re, double* im, int rows_in, FftScratch& scratch) const {
    // Rows that are zero stay zero along their own length.
    rows(re, im, std::min(rows_in, h_), -1, scratch);
    columns(re, im, h_, w_, w_, -1);
}

void Fft2d::inverse(double* re, double* im, int rows_out, FftScratch& scratch) const {
    columns(re, im, h_, w_, w_, 1);
    rows(re, im, std::min(rows_out, h_), 1, scratch);
}

double fft_correlation_error_bound(std::size_t points, double norm_products) {
    const double ulp = std::ldexp(1.0, -53);
    return 3750.0 * ulp * std::log2(double(points)) * std::sqrt(double(points)) * norm_products;
}

}  // namespace vqtex::dsp
