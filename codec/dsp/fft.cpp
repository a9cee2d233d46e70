// fft.cpp - the radix-2 transform of fft.hpp, two stages a pass: every pass
// runs along the columns of a row-major array, one row of values at a time,
// so the innermost loop is a plain loop over contiguous doubles that the
// compiler vectorises; the other axis goes through a transposed copy. The
// forward transform decimates in frequency (natural order in, bit-reversed
// out) and the inverse in time (bit-reversed in, natural out), so neither
// reorders anything: the spectrum stays in the order the first left it,
// which products and the inverse do not mind.
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

// One butterfly of decimation in time on n columns: a + w b and a - w b,
// w = wr + i wi.
VQTEX_FFT_CLONES
void dit2(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi, double wr,
          double wi, int n) {
    for (int x = 0; x < n; ++x) {
        const double tr = br[x] * wr - bi[x] * wi, ti = br[x] * wi + bi[x] * wr;
        br[x] = ar[x] - tr;
        bi[x] = ai[x] - ti;
        ar[x] += tr;
        ai[x] += ti;
    }
}

// Two stages of decimation in time at once on n columns (radix 2
// squared): with a, b, c, d the rows j, j + L/2, j + L and j + 3L/2 of a
// group of 2L, the stage of L on the pairs (a, b) and (c, d) with twiddle
// w1, the stage of 2L then on (a, c) with w2 and (b, d) with w3: the same
// arithmetic as the two stages one after the other, in one pass over
// memory.
VQTEX_FFT_CLONES
void dit4(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi,
          double* __restrict cr, double* __restrict ci, double* __restrict dr, double* __restrict di, double w1r,
          double w1i, double w2r, double w2i, double w3r, double w3i, int n) {
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

// The last stage of decimation in frequency (its twiddle is 1) on n
// columns, in place: a + b and a - b.
VQTEX_FFT_CLONES
void dif2(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi, int n) {
    for (int x = 0; x < n; ++x) {
        const double tr = ar[x] - br[x], ti = ai[x] - bi[x];
        ar[x] += br[x];
        ai[x] += bi[x];
        br[x] = tr;
        bi[x] = ti;
    }
}

// Two stages of decimation in frequency at once on n columns, in place:
// with a, b, c, d the rows j, j + L/4, j + L/2 and j + 3L/4 of a group of
// L, the stage of L on (a, c) with twiddle w1 and (b, d) with w3, then the
// stage of L/2 on (a, b) and (c, d) with w2.
VQTEX_FFT_CLONES
void dif4(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi,
          double* __restrict cr, double* __restrict ci, double* __restrict dr, double* __restrict di, double w1r,
          double w1i, double w2r, double w2i, double w3r, double w3i, int n) {
    for (int x = 0; x < n; ++x) {
        const double a1r = ar[x] + cr[x], a1i = ai[x] + ci[x], e1r = ar[x] - cr[x], e1i = ai[x] - ci[x];
        const double b1r = br[x] + dr[x], b1i = bi[x] + di[x], f1r = br[x] - dr[x], f1i = bi[x] - di[x];
        const double c1r = e1r * w1r - e1i * w1i, c1i = e1r * w1i + e1i * w1r;
        const double d1r = f1r * w3r - f1i * w3i, d1i = f1r * w3i + f1i * w3r;
        const double gr = a1r - b1r, gi = a1i - b1i, hr = c1r - d1r, hi = c1i - d1i;
        ar[x] = a1r + b1r;
        ai[x] = a1i + b1i;
        br[x] = gr * w2r - gi * w2i;
        bi[x] = gr * w2i + gi * w2r;
        cr[x] = c1r + d1r;
        ci[x] = c1i + d1i;
        dr[x] = hr * w2r - hi * w2i;
        di[x] = hr * w2i + hi * w2r;
    }
}

// dif4 on rows whose c and d are zero (the upper half of a column that
// holds values in its lower half only), for the values p of a and q of b:
// the same values as dif4 on the zeros, c and d written without being
// read.
struct Dif4Out {
    double ar, ai, br, bi, cr, ci, dr, di;
};
inline Dif4Out dif4_upper_zero_values(double pr, double pi, double qr, double qi, double w1r, double w1i, double w2r,
                                      double w2i, double w3r, double w3i) {
    const double c1r = pr * w1r - pi * w1i, c1i = pr * w1i + pi * w1r;
    const double d1r = qr * w3r - qi * w3i, d1i = qr * w3i + qi * w3r;
    const double gr = pr - qr, gi = pi - qi, hr = c1r - d1r, hi = c1i - d1i;
    return {pr + qr, pi + qi, gr * w2r - gi * w2i, gr * w2i + gi * w2r,
            c1r + d1r, c1i + d1i, hr * w2r - hi * w2i, hr * w2i + hi * w2r};
}

// That in place: a and b read and written, c and d written.
VQTEX_FFT_CLONES
void dif4_upper_zero(double* __restrict ar, double* __restrict ai, double* __restrict br, double* __restrict bi,
                     double* __restrict cr, double* __restrict ci, double* __restrict dr, double* __restrict di,
                     double w1r, double w1i, double w2r, double w2i, double w3r, double w3i, int n) {
    for (int x = 0; x < n; ++x) {
        const Dif4Out o = dif4_upper_zero_values(ar[x], ai[x], br[x], bi[x], w1r, w1i, w2r, w2i, w3r, w3i);
        ar[x] = o.ar, ai[x] = o.ai, br[x] = o.br, bi[x] = o.bi, cr[x] = o.cr, ci[x] = o.ci, dr[x] = o.dr, di[x] = o.di;
    }
}

// And from the source rows sa, sb to the rows a, b, c, d of another array.
VQTEX_FFT_CLONES
void dif4_upper_zero_from(const double* __restrict sar, const double* __restrict sai, const double* __restrict sbr,
                          const double* __restrict sbi, double* __restrict ar, double* __restrict ai,
                          double* __restrict br, double* __restrict bi, double* __restrict cr, double* __restrict ci,
                          double* __restrict dr, double* __restrict di, double w1r, double w1i, double w2r, double w2i,
                          double w3r, double w3i, int n) {
    for (int x = 0; x < n; ++x) {
        const Dif4Out o = dif4_upper_zero_values(sar[x], sai[x], sbr[x], sbi[x], w1r, w1i, w2r, w2i, w3r, w3i);
        ar[x] = o.ar, ai[x] = o.ai, br[x] = o.br, bi[x] = o.bi, cr[x] = o.cr, ci[x] = o.ci, dr[x] = o.dr, di[x] = o.di;
    }
}

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

void Fft2d::twiddle(int k, int len, int sign, double& wr, double& wi) const {
    const std::size_t i = std::size_t(k) * std::size_t(n_ / len);
    wr = cos_[i];
    wi = sign * sin_[i];
}

bool Fft2d::pruned(int n, int rows_in) { return n >= 4 && rows_in <= n / 2; }

Fft2d::DifTwiddles Fft2d::dif_twiddles(int j, int len, int sign) const {
    // Row j of a group of len, and j + len/4, at the stage of len; row j at
    // the stage of len/2.
    DifTwiddles t;
    twiddle(j, len, sign, t.w1r, t.w1i);
    twiddle(j + len / 4, len, sign, t.w3r, t.w3i);
    twiddle(j, len / 2, sign, t.w2r, t.w2i);
    return t;
}

void Fft2d::dif(const double* sre, const double* sim, int src_stride, double* re, double* im, int stride, int n,
                int cols, int rows_in, int sign) const {
    const auto row = [&](double* p, int r) { return p + std::size_t(r) * std::size_t(stride); };
    const auto src = [&](const double* p, int r) { return p + std::size_t(r) * std::size_t(src_stride); };
    int len = n;
    if (pruned(n, rows_in)) {
        // The first two stages from the source's lower half.
        const int q = n / 4;
        for (int j = 0; j < q; ++j) {
            const DifTwiddles t = dif_twiddles(j, n, sign);
            const double w1r = t.w1r, w1i = t.w1i, w2r = t.w2r, w2i = t.w2i, w3r = t.w3r, w3i = t.w3i;
            if (sre == re)
                dif4_upper_zero(row(re, j), row(im, j), row(re, j + q), row(im, j + q), row(re, j + 2 * q),
                                row(im, j + 2 * q), row(re, j + 3 * q), row(im, j + 3 * q), w1r, w1i, w2r, w2i, w3r,
                                w3i, cols);
            else
                dif4_upper_zero_from(src(sre, j), src(sim, j), src(sre, j + q), src(sim, j + q), row(re, j),
                                     row(im, j), row(re, j + q), row(im, j + q), row(re, j + 2 * q), row(im, j + 2 * q),
                                     row(re, j + 3 * q), row(im, j + 3 * q), w1r, w1i, w2r, w2i, w3r, w3i, cols);
        }
        len = n / 4;
    } else if (sre != re) {
        for (int r = 0; r < n; ++r) {
            std::copy_n(src(sre, r), cols, row(re, r));
            std::copy_n(src(sim, r), cols, row(im, r));
        }
    }
    // The stages of L and L/2 two at a time from L down, then the last one
    // (L = 2) alone when their count is odd.
    for (; len >= 4; len >>= 2) {
        const int q = len / 4;
        for (int j = 0; j < q; ++j) {
            const DifTwiddles t = dif_twiddles(j, len, sign);
            const double w1r = t.w1r, w1i = t.w1i, w2r = t.w2r, w2i = t.w2i, w3r = t.w3r, w3i = t.w3i;
            for (int a = j; a < n; a += len)
                dif4(row(re, a), row(im, a), row(re, a + q), row(im, a + q), row(re, a + 2 * q), row(im, a + 2 * q),
                     row(re, a + 3 * q), row(im, a + 3 * q), w1r, w1i, w2r, w2i, w3r, w3i, cols);
        }
    }
    if (len == 2)
        for (int a = 0; a < n; a += 2) dif2(row(re, a), row(im, a), row(re, a + 1), row(im, a + 1), cols);
}

void Fft2d::dit(double* re, double* im, int n, int cols, int stride, int sign) const {
    const auto row = [&](double* p, int r) { return p + std::size_t(r) * std::size_t(stride); };
    // The stages of L and 2L two at a time from L = 2 up, then the last one
    // (L = n) alone when their count is odd.
    int len = 2;
    for (; 2 * len <= n; len <<= 2) {
        const int half = len / 2;
        for (int j = 0; j < half; ++j) {
            double w1r, w1i, w2r, w2i, w3r, w3i;
            twiddle(j, len, sign, w1r, w1i);
            twiddle(j, 2 * len, sign, w2r, w2i);
            twiddle(j + half, 2 * len, sign, w3r, w3i);
            for (int base = 0; base < n; base += 2 * len)
                dit4(row(re, base + j), row(im, base + j), row(re, base + j + half), row(im, base + j + half),
                     row(re, base + j + len), row(im, base + j + len), row(re, base + j + len + half),
                     row(im, base + j + len + half), w1r, w1i, w2r, w2i, w3r, w3i, cols);
        }
    }
    if (len <= n) {
        const int half = len / 2;
        for (int j = 0; j < half; ++j) {
            double wr, wi;
            twiddle(j, len, sign, wr, wi);
            for (int base = 0; base < n; base += len)
                dit2(row(re, base + j), row(im, base + j), row(re, base + j + half), row(im, base + j + half), wr, wi,
                     cols);
        }
    }
}

void Fft2d::forward(double* re, double* im, int rows_in, int cols_in, FftScratch& scratch) const {
    rows_in = std::clamp(rows_in, 1, h_);
    cols_in = std::clamp(cols_in, 1, w_);
    // The transposed columns and the zeros after them, up to the half the
    // second pass reads when it is pruned.
    const std::size_t need = std::size_t(pruned(w_, cols_in) ? w_ / 2 : w_) * std::size_t(h_);
    if (scratch.re.size() < need) {
        scratch.re.resize(need);
        scratch.im.resize(need);
    }
    // Rows past rows_in are read as zero: set to zero here, up to the
    // upper half, which is not read at all when they cover it.
    for (int r = rows_in, end = pruned(h_, rows_in) ? h_ / 2 : h_; r < end; ++r) {
        std::fill_n(re + std::size_t(r) * std::size_t(w_), cols_in, 0.0);
        std::fill_n(im + std::size_t(r) * std::size_t(w_), cols_in, 0.0);
    }
    // Down the first cols_in columns (the others are zero and stay so),
    // the frequencies in bit-reversed order; then across, on the
    // transposed columns, into re and im as w_ rows of h_.
    dif(re, im, w_, re, im, w_, h_, cols_in, rows_in, -1);
    double* tre = scratch.re.data();
    double* tim = scratch.im.data();
    transpose(re, h_, cols_in, w_, tre, h_);
    transpose(im, h_, cols_in, w_, tim, h_);
    std::fill(tre + std::size_t(cols_in) * std::size_t(h_), tre + need, 0.0);
    std::fill(tim + std::size_t(cols_in) * std::size_t(h_), tim + need, 0.0);
    dif(tre, tim, h_, re, im, h_, w_, h_, cols_in, -1);
}

void Fft2d::inverse(double* re, double* im, int rows_out, int cols_out, FftScratch& scratch) const {
    rows_out = std::clamp(rows_out, 1, h_);
    cols_out = std::clamp(cols_out, 1, w_);
    const std::size_t need = std::size_t(cols_out) * std::size_t(h_);
    if (scratch.re.size() < need) {
        scratch.re.resize(need);
        scratch.im.resize(need);
    }
    // Across (re and im hold w_ rows of h_, the frequencies in
    // bit-reversed order), then down the first cols_out columns on their
    // transposed copy, and the first rows_out rows back in place.
    dit(re, im, w_, h_, h_, 1);
    double* tre = scratch.re.data();
    double* tim = scratch.im.data();
    transpose(re, cols_out, h_, h_, tre, cols_out);
    transpose(im, cols_out, h_, h_, tim, cols_out);
    dit(tre, tim, h_, cols_out, cols_out, 1);
    for (int r = 0; r < rows_out; ++r) {
        std::copy_n(tre + std::size_t(r) * std::size_t(cols_out), cols_out, re + std::size_t(r) * std::size_t(w_));
        std::copy_n(tim + std::size_t(r) * std::size_t(cols_out), cols_out, im + std::size_t(r) * std::size_t(w_));
    }
}

VQTEX_FFT_CLONES
void conj_product_in_place(double* __restrict zr, double* __restrict zi, const double* __restrict wr,
                           const double* __restrict wi, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const double re = zr[i] * wr[i] + zi[i] * wi[i], im = zr[i] * wi[i] - zi[i] * wr[i];
        zr[i] = re;
        zi[i] = im;
    }
}

VQTEX_FFT_CLONES
void conj_product_into(const double* __restrict zr, const double* __restrict zi, const double* __restrict wr,
                       const double* __restrict wi, double* __restrict sr, double* __restrict si, std::size_t n,
                       bool add) {
    if (add) {
        for (std::size_t i = 0; i < n; ++i) {
            sr[i] += zr[i] * wr[i] + zi[i] * wi[i];
            si[i] += zr[i] * wi[i] - zi[i] * wr[i];
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) {
            sr[i] = zr[i] * wr[i] + zi[i] * wi[i];
            si[i] = zr[i] * wi[i] - zi[i] * wr[i];
        }
    }
}

double fft_correlation_error_bound(std::size_t points, double norm_products) {
    const double ulp = std::ldexp(1.0, -53);
    return 3750.0 * ulp * std::log2(double(points)) * std::sqrt(double(points)) * norm_products;
}

}  // namespace vqtex::dsp
