// linear_kernels_simd.hpp - the appearance space's linear algebra
// (Lefebvre & Hoppe 2006 section 3: the PCA of the example's windows and
// the projection of every window on its axes; engine/appearance.cpp) as
// kernel templates over a register width, where the compiler's own
// vectorisation of linear_kernels.hpp's definitions falls short:
// - Kernels::project_pairs: each register holds one 32-bit sum per pixel;
//   the sums of all kWindowTapValues axes stay in registers while every
//   entry (two window values a pixel, as 16-bit pairs) is read once and
//   multiplied with each axis's pair of weights in one multiply-add of
//   pairs. Adding a weight times a row for one axis at a time read and
//   wrote the sums 38 times per axis and widened every value first.
// - Kernels::gram_i16: blocks of products whose sums stay in registers.
// - Kernels::matvec_i32: signed 32x32->64-bit multiplies of even and odd
//   lanes (the compiler widened both operands and used a 64-bit multiply).
//
// Every operation of the first two but the multiply-add acts within 128-bit
// lanes, so one template serves SSE2, AVX2 and AVX-512: a Lanes type gives
// the register, its operations and how its 128-bit lanes of four pixels
// are stored in order. The sums wrap modulo a power of two as the
// definitions' do, and the projection's rounding is the same integer while
// Kernels::project_pairs' bounds hold. Internal linkage for the reason
// given in descent.hpp.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "dsp/dsp.hpp"
#include "dsp/linear_kernels.hpp"

namespace vqtex::dsp::detail {
namespace {

// Four pixels a register: SSE2 (the wider types' operations are these per
// 128-bit lane).
struct Sse2Lanes {
    using Reg = __m128i;
    static constexpr std::size_t kPixels = 4;
    static constexpr std::size_t kGramBlock = 3;  // rows and columns of products a block
    static Reg zero() { return _mm_setzero_si128(); }
    static Reg set1(int32_t v) { return _mm_set1_epi32(v); }
    static Reg set1_16(int16_t v) { return _mm_set1_epi16(v); }
    static Reg load(const int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
    static Reg madd_add(Reg sum, Reg x, int32_t w) { return _mm_add_epi32(sum, _mm_madd_epi16(x, _mm_set1_epi32(w))); }
    static Reg madd_acc(Reg sum, Reg a, Reg b) { return _mm_add_epi32(sum, _mm_madd_epi16(a, b)); }
    static uint32_t hsum(Reg v) {
        v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(1, 0, 3, 2)));
        v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(2, 3, 0, 1)));
        return uint32_t(_mm_cvtsi128_si32(v));
    }
    static Reg sub(Reg a, Reg b) { return _mm_sub_epi32(a, b); }
    static Reg srai15(Reg a) { return _mm_srai_epi32(a, 15); }
    static Reg packs(Reg a, Reg b) { return _mm_packs_epi32(a, b); }
    static Reg min16(Reg a, Reg b) { return _mm_min_epi16(a, b); }
    static Reg max16(Reg a, Reg b) { return _mm_max_epi16(a, b); }
    static Reg unpacklo16(Reg a, Reg b) { return _mm_unpacklo_epi16(a, b); }
    static Reg unpackhi16(Reg a, Reg b) { return _mm_unpackhi_epi16(a, b); }
    static Reg unpacklo64(Reg a, Reg b) { return _mm_unpacklo_epi64(a, b); }
    static Reg unpackhi64(Reg a, Reg b) { return _mm_unpackhi_epi64(a, b); }
    static void store_pixels(int16_t* out, Reg p0, Reg p1, Reg p2, Reg p3) {
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out), p0);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 8), p1);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 16), p2);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 24), p3);
    }
};

#if defined(__AVX2__)
// Eight pixels a register: lane 0 holds pixels 0-3, lane 1 pixels 4-7.
struct Avx2Lanes {
    using Reg = __m256i;
    static constexpr std::size_t kPixels = 8;
    static constexpr std::size_t kGramBlock = 3;  // rows and columns of products a block
    static Reg zero() { return _mm256_setzero_si256(); }
    static Reg set1(int32_t v) { return _mm256_set1_epi32(v); }
    static Reg set1_16(int16_t v) { return _mm256_set1_epi16(v); }
    static Reg load(const int16_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
    static Reg madd_add(Reg sum, Reg x, int32_t w) {
        return _mm256_add_epi32(sum, _mm256_madd_epi16(x, _mm256_set1_epi32(w)));
    }
    static Reg madd_acc(Reg sum, Reg a, Reg b) { return _mm256_add_epi32(sum, _mm256_madd_epi16(a, b)); }
    static uint32_t hsum(Reg v) {
        return Sse2Lanes::hsum(_mm_add_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1)));
    }
    static Reg sub(Reg a, Reg b) { return _mm256_sub_epi32(a, b); }
    static Reg srai15(Reg a) { return _mm256_srai_epi32(a, 15); }
    static Reg packs(Reg a, Reg b) { return _mm256_packs_epi32(a, b); }
    static Reg min16(Reg a, Reg b) { return _mm256_min_epi16(a, b); }
    static Reg max16(Reg a, Reg b) { return _mm256_max_epi16(a, b); }
    static Reg unpacklo16(Reg a, Reg b) { return _mm256_unpacklo_epi16(a, b); }
    static Reg unpackhi16(Reg a, Reg b) { return _mm256_unpackhi_epi16(a, b); }
    static Reg unpacklo64(Reg a, Reg b) { return _mm256_unpacklo_epi64(a, b); }
    static Reg unpackhi64(Reg a, Reg b) { return _mm256_unpackhi_epi64(a, b); }
    static void store_pixels(int16_t* out, Reg p0, Reg p1, Reg p2, Reg p3) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_permute2x128_si256(p0, p1, 0x20));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 16), _mm256_permute2x128_si256(p2, p3, 0x20));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 32), _mm256_permute2x128_si256(p0, p1, 0x31));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 48), _mm256_permute2x128_si256(p2, p3, 0x31));
    }
};
#endif

#if defined(__AVX512F__) && defined(__AVX512BW__)
// Sixteen pixels a register: lane k holds pixels 4k to 4k + 3.
struct Avx512Lanes {
    using Reg = __m512i;
    static constexpr std::size_t kPixels = 16;
    static constexpr std::size_t kGramBlock = 4;  // rows and columns of products a block
    static Reg zero() { return _mm512_setzero_si512(); }
    static Reg set1(int32_t v) { return _mm512_set1_epi32(v); }
    static Reg set1_16(int16_t v) { return _mm512_set1_epi16(v); }
    static Reg load(const int16_t* p) { return _mm512_loadu_si512(p); }
    static Reg madd_add(Reg sum, Reg x, int32_t w) {
        return _mm512_add_epi32(sum, _mm512_madd_epi16(x, _mm512_set1_epi32(w)));
    }
    static Reg madd_acc(Reg sum, Reg a, Reg b) { return _mm512_add_epi32(sum, _mm512_madd_epi16(a, b)); }
    static uint32_t hsum(Reg v) { return uint32_t(_mm512_reduce_add_epi32(v)); }
    static Reg sub(Reg a, Reg b) { return _mm512_sub_epi32(a, b); }
    static Reg srai15(Reg a) { return _mm512_srai_epi32(a, 15); }
    static Reg packs(Reg a, Reg b) { return _mm512_packs_epi32(a, b); }
    static Reg min16(Reg a, Reg b) { return _mm512_min_epi16(a, b); }
    static Reg max16(Reg a, Reg b) { return _mm512_max_epi16(a, b); }
    static Reg unpacklo16(Reg a, Reg b) { return _mm512_unpacklo_epi16(a, b); }
    static Reg unpackhi16(Reg a, Reg b) { return _mm512_unpackhi_epi16(a, b); }
    static Reg unpacklo64(Reg a, Reg b) { return _mm512_unpacklo_epi64(a, b); }
    static Reg unpackhi64(Reg a, Reg b) { return _mm512_unpackhi_epi64(a, b); }
    static void store_pixels(int16_t* out, Reg p0, Reg p1, Reg p2, Reg p3) {
        // Lanes 0-1 of p0, p1 side by side, then of p2, p3 (likewise lanes
        // 2-3); picking every other lane of those gives pixels in order.
        const Reg a = _mm512_shuffle_i64x2(p0, p1, 0x44), b = _mm512_shuffle_i64x2(p2, p3, 0x44);
        const Reg c = _mm512_shuffle_i64x2(p0, p1, 0xEE), d = _mm512_shuffle_i64x2(p2, p3, 0xEE);
        _mm512_storeu_si512(out, _mm512_shuffle_i64x2(a, b, 0x88));
        _mm512_storeu_si512(out + 32, _mm512_shuffle_i64x2(a, b, 0xDD));
        _mm512_storeu_si512(out + 64, _mm512_shuffle_i64x2(c, d, 0x88));
        _mm512_storeu_si512(out + 96, _mm512_shuffle_i64x2(c, d, 0xDD));
    }
};
#endif

#if defined(__AVX512VNNI__) && defined(__AVX512BW__)
// VNNI's multiply-add of pairs adds to the sum in the same instruction
// (vpdpwssd, which wraps modulo 2^32 like the separate add).
struct Avx512VnniLanes : Avx512Lanes {
    static Reg madd_add(Reg sum, Reg x, int32_t w) { return _mm512_dpwssd_epi32(sum, x, _mm512_set1_epi32(w)); }
    static Reg madd_acc(Reg sum, Reg a, Reg b) { return _mm512_dpwssd_epi32(sum, a, b); }
};
#endif

template <class Lanes>
void project_pairs_simd(const int16_t* const* rows, const int32_t* weights, std::size_t count, std::size_t n,
                        const int32_t* offset, int32_t limit, int16_t* out) {
    using Reg = typename Lanes::Reg;
    constexpr std::size_t kPixels = Lanes::kPixels;
    constexpr int kAxes = kWindowTapValues;
    static_assert(kAxes == 8, "the transposition below makes rows of 8 values");
    // The offset less the rounding term, subtracted once per sum.
    Reg shift[kAxes];
    for (int a = 0; a < kAxes; ++a) shift[a] = Lanes::set1(offset[a] - (1 << 14));
    const Reg high = Lanes::set1_16(int16_t(limit)), low = Lanes::set1_16(int16_t(-limit));
    std::size_t i = 0;
    for (; i + kPixels <= n; i += kPixels) {
        Reg sum[kAxes];
        for (int a = 0; a < kAxes; ++a) sum[a] = Lanes::zero();
        for (std::size_t e = 0; e < count; ++e) {
            const Reg x = Lanes::load(rows[e] + 2 * i);
            const int32_t* w = weights + e * kAxes;
            for (int a = 0; a < kAxes; ++a) sum[a] = Lanes::madd_add(sum[a], x, w[a]);
        }
        // Rounded from Q15; within 16 bits but for the saturation of the
        // pack, which the clamp below (|limit| < 2^15) makes no difference to.
        for (int a = 0; a < kAxes; ++a) sum[a] = Lanes::srai15(Lanes::sub(sum[a], shift[a]));
        Reg u[4];
        for (int k = 0; k < 4; ++k) u[k] = Lanes::max16(Lanes::min16(Lanes::packs(sum[2 * k], sum[2 * k + 1]), high), low);
        // Per 128-bit lane, u[k] holds axes 2k and 2k + 1 of four pixels;
        // three rounds of interleaving give each pixel's eight values.
        const Reg t0 = Lanes::unpacklo16(u[0], u[1]), t1 = Lanes::unpackhi16(u[0], u[1]);
        const Reg t2 = Lanes::unpacklo16(u[2], u[3]), t3 = Lanes::unpackhi16(u[2], u[3]);
        const Reg s0 = Lanes::unpacklo16(t0, t1), s1 = Lanes::unpackhi16(t0, t1);
        const Reg s2 = Lanes::unpacklo16(t2, t3), s3 = Lanes::unpackhi16(t2, t3);
        Lanes::store_pixels(out + i * kAxes, Lanes::unpacklo64(s0, s2), Lanes::unpackhi64(s0, s2),
                            Lanes::unpacklo64(s1, s3), Lanes::unpackhi64(s1, s3));
    }
    project_pairs_range(rows, weights, count, i, n, offset, limit, out);
}


// Kernels::gram_i16: blocks of kGramBlock x kGramBlock products, whose sums
// stay in registers while the block's columns are read once (a dot product
// per entry read both columns for each). A block past the last row or
// column reads the last one again and keeps nothing of it; the values after
// the last whole register are added one by one.
template <class Lanes>
void gram_i16_simd(const int16_t* columns, std::size_t dims, std::size_t count, std::size_t first, std::size_t last,
                   uint32_t* products) {
    using Reg = typename Lanes::Reg;
    constexpr std::size_t kBlock = Lanes::kGramBlock;
    constexpr std::size_t kStep = 2 * Lanes::kPixels;  // 16-bit values a register
    const std::size_t whole = count / kStep * kStep;
    for (std::size_t i0 = first; i0 < last; i0 += kBlock)
        for (std::size_t j0 = i0; j0 < dims; j0 += kBlock) {
            const int16_t* a[kBlock];
            const int16_t* b[kBlock];
            for (std::size_t r = 0; r < kBlock; ++r) {
                a[r] = columns + std::min(i0 + r, dims - 1) * count;
                b[r] = columns + std::min(j0 + r, dims - 1) * count;
            }
            Reg sum[kBlock][kBlock];
            for (std::size_t r = 0; r < kBlock; ++r)
                for (std::size_t c = 0; c < kBlock; ++c) sum[r][c] = Lanes::zero();
            for (std::size_t s = 0; s < whole; s += kStep) {
                Reg x[kBlock];
                for (std::size_t r = 0; r < kBlock; ++r) x[r] = Lanes::load(a[r] + s);
                for (std::size_t c = 0; c < kBlock; ++c) {
                    const Reg y = Lanes::load(b[c] + s);
                    for (std::size_t r = 0; r < kBlock; ++r) sum[r][c] = Lanes::madd_acc(sum[r][c], x[r], y);
                }
            }
            for (std::size_t r = 0; r < kBlock; ++r)
                for (std::size_t c = 0; c < kBlock; ++c) {
                    const std::size_t i = i0 + r, j = j0 + c;
                    if (i >= last || j >= dims || j < i) continue;
                    uint32_t total = Lanes::hsum(sum[r][c]);
                    for (std::size_t s = whole; s < count; ++s) total += uint32_t(int32_t(a[r][s]) * int32_t(b[c][s]));
                    products[i * dims + j] = total;
                }
        }
}


// Kernels::matvec_i32 on C registers of outputs at a time, each held as
// two registers of 64-bit sums: the products of the even 32-bit lanes and
// those of the odd lanes (a signed 32x32->64-bit multiply takes the low half
// of each 64-bit lane). Ops gives the register type; lanes past n are
// loaded as zeros and never stored.
template <class Ops, int C>
void matvec_pass(const int32_t* m, const int32_t* v, std::size_t n, std::size_t i0, int64_t* out) {
    using Reg = typename Ops::Reg;
    constexpr std::size_t kValues = Ops::kValues;  // 32-bit values a register
    Reg even[C], odd[C];
    for (int c = 0; c < C; ++c) even[c] = odd[c] = Ops::zero();
    for (std::size_t j = 0; j < n; ++j) {
        const Reg factor = Ops::set1(v[j]);
        const int32_t* row = m + j * n + i0;
        for (int c = 0; c < C; ++c) {
            const Reg r = Ops::load_upto(row + std::size_t(c) * kValues, n - i0 - std::size_t(c) * kValues);
            even[c] = Ops::add64(even[c], Ops::mul32(r, factor));
            odd[c] = Ops::add64(odd[c], Ops::mul32(Ops::high32(r), factor));
        }
    }
    for (int c = 0; c < C; ++c) {
        alignas(64) int64_t e[kValues / 2], o[kValues / 2];
        Ops::store(e, even[c]);
        Ops::store(o, odd[c]);
        for (std::size_t k = 0; k < kValues / 2; ++k) {
            const std::size_t i = i0 + std::size_t(c) * kValues + 2 * k;
            if (i < n) out[i] = e[k];
            if (i + 1 < n) out[i + 1] = o[k];
        }
    }
}

template <class Ops>
void matvec_i32_simd(const int32_t* m, const int32_t* v, std::size_t n, int64_t* out) {
    constexpr std::size_t kValues = Ops::kValues;
    for (std::size_t i0 = 0; i0 < n;) {
        const std::size_t chunks = std::min<std::size_t>((n - i0 + kValues - 1) / kValues, Ops::kMaxChunks);
        switch (chunks) {
        case 1: matvec_pass<Ops, 1>(m, v, n, i0, out); break;
        case 2: matvec_pass<Ops, 2>(m, v, n, i0, out); break;
        case 3: matvec_pass<Ops, 3>(m, v, n, i0, out); break;
        case 4: matvec_pass<Ops, 4>(m, v, n, i0, out); break;
        case 5: matvec_pass<Ops, 5>(m, v, n, i0, out); break;
        default: matvec_pass<Ops, 6>(m, v, n, i0, out); break;
        }
        i0 += chunks * kValues;
    }
}

#if defined(__AVX2__)
struct Avx2Matvec {
    using Reg = __m256i;
    static constexpr std::size_t kValues = 8;
    static constexpr std::size_t kMaxChunks = 6;  // 12 sums, and the row, its odd half and v[j]
    static Reg zero() { return _mm256_setzero_si256(); }
    static Reg set1(int32_t x) { return _mm256_set1_epi32(x); }
    static Reg load_upto(const int32_t* p, std::size_t left) {
        if (left >= kValues) return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
        const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        return _mm256_maskload_epi32(p, _mm256_cmpgt_epi32(_mm256_set1_epi32(int32_t(left)), lane));
    }
    static Reg mul32(Reg a, Reg b) { return _mm256_mul_epi32(a, b); }
    static Reg high32(Reg a) { return _mm256_srli_epi64(a, 32); }
    static Reg add64(Reg a, Reg b) { return _mm256_add_epi64(a, b); }
    static void store(int64_t* p, Reg a) { _mm256_store_si256(reinterpret_cast<__m256i*>(p), a); }
};
#endif

#if defined(__AVX512F__)
struct Avx512Matvec {
    using Reg = __m512i;
    static constexpr std::size_t kValues = 16;
    static constexpr std::size_t kMaxChunks = 6;  // 96 outputs a pass: a 4-channel window's 100 in two
    static Reg zero() { return _mm512_setzero_si512(); }
    static Reg set1(int32_t x) { return _mm512_set1_epi32(x); }
    static Reg load_upto(const int32_t* p, std::size_t left) {
        const __mmask16 mask = left >= kValues ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
        return _mm512_maskz_loadu_epi32(mask, p);
    }
    static Reg mul32(Reg a, Reg b) { return _mm512_mul_epi32(a, b); }
    static Reg high32(Reg a) { return _mm512_srli_epi64(a, 32); }
    static Reg add64(Reg a, Reg b) { return _mm512_add_epi64(a, b); }
    static void store(int64_t* p, Reg a) { _mm512_store_si512(p, a); }
};
#endif

}  // namespace
}  // namespace vqtex::dsp::detail
