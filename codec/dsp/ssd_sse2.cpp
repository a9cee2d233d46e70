// ssd_sse2.cpp - SSE2 distance kernels (every x86-64 CPU has them).
// Bit-identical to ssd_scalar.cpp: exact 32-bit integer sums.
#include "dsp/descent.hpp"
#include "dsp/dsp.hpp"
#include "dsp/linear_kernels.hpp"

#if defined(__SSE2__) && !defined(VQTEX_SCALAR_ONLY)
#include "dsp/linear_kernels_simd.hpp"
#include "dsp/packed_pixels_sse2.hpp"
#include "dsp/window_ssd.hpp"
#include <emmintrin.h>

namespace vqtex::dsp {
namespace {

inline __m128i ssd16(const uint8_t* a, const uint8_t* b) {
    const __m128i zero = _mm_setzero_si128();
    const __m128i va = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a));
    const __m128i vb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b));
    const __m128i dlo = _mm_sub_epi16(_mm_unpacklo_epi8(va, zero), _mm_unpacklo_epi8(vb, zero));
    const __m128i dhi = _mm_sub_epi16(_mm_unpackhi_epi8(va, zero), _mm_unpackhi_epi8(vb, zero));
    return _mm_add_epi32(_mm_madd_epi16(dlo, dlo), _mm_madd_epi16(dhi, dhi));
}

inline uint32_t hsum(__m128i v) {
    v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(1, 0, 3, 2)));
    v = _mm_add_epi32(v, _mm_shuffle_epi32(v, _MM_SHUFFLE(2, 3, 0, 1)));
    return uint32_t(_mm_cvtsi128_si32(v));
}

uint32_t ssd_sse2(const uint8_t* a, const uint8_t* b, std::size_t n) {
    __m128i acc = _mm_setzero_si128();
    for (std::size_t i = 0; i < n; i += 16) acc = _mm_add_epi32(acc, ssd16(a + i, b + i));
    return hsum(acc);
}

uint32_t nearest_sse2(const uint8_t* query, const uint8_t* rows, std::size_t stride,
                      std::size_t n, std::size_t count, uint32_t* best_distance) {
    uint32_t best = *best_distance;
    uint32_t best_index = UINT32_MAX;
    for (std::size_t r = 0; r < count; ++r) {
        const uint8_t* row = rows + r * stride;
        __m128i acc = _mm_setzero_si128();
        std::size_t i = 0;
        uint32_t sum = 0;
        // Check the bound every 64 bytes: often enough to abandon most rows
        // early, rarely enough to keep the horizontal sums cheap.
        while (i < n) {
            const std::size_t end = (n - i > 64) ? i + 64 : n;
            for (; i < end; i += 16) acc = _mm_add_epi32(acc, ssd16(query + i, row + i));
            sum = hsum(acc);
            if (sum >= best) break;
        }
        if (i >= n && sum < best) {
            best = sum;
            best_index = uint32_t(r);
        }
    }
    *best_distance = best;
    return best_index;
}

int32_t dot_sse2(const uint8_t* a, const int16_t* w, std::size_t n) {
    const __m128i zero = _mm_setzero_si128();
    __m128i acc = _mm_setzero_si128();
    for (std::size_t i = 0; i < n; i += 16) {
        const __m128i va = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i));
        const __m128i w0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(w + i));
        const __m128i w1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(w + i + 8));
        acc = _mm_add_epi32(acc, _mm_madd_epi16(_mm_unpacklo_epi8(va, zero), w0));
        acc = _mm_add_epi32(acc, _mm_madd_epi16(_mm_unpackhi_epi8(va, zero), w1));
    }
    return int32_t(hsum(acc));
}

VQTEX_DSP_INLINE void dot2_sse2(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
    const __m128i zero = _mm_setzero_si128();
    __m128i acc0 = _mm_setzero_si128(), acc1 = _mm_setzero_si128();
    for (std::size_t i = 0; i < n; i += 16) {
        const __m128i q = _mm_loadu_si128(reinterpret_cast<const __m128i*>(query + i));
        // Sign-extend: each byte into the high half of a 16-bit lane, then an
        // arithmetic shift down.
        const __m128i qlo = _mm_srai_epi16(_mm_unpacklo_epi8(zero, q), 8);
        const __m128i qhi = _mm_srai_epi16(_mm_unpackhi_epi8(zero, q), 8);
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + i));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + n + i));
        acc0 = _mm_add_epi32(acc0, _mm_add_epi32(_mm_madd_epi16(qlo, _mm_unpacklo_epi8(a, zero)),
                                                 _mm_madd_epi16(qhi, _mm_unpackhi_epi8(a, zero))));
        acc1 = _mm_add_epi32(acc1, _mm_add_epi32(_mm_madd_epi16(qlo, _mm_unpacklo_epi8(b, zero)),
                                                 _mm_madd_epi16(qhi, _mm_unpackhi_epi8(b, zero))));
    }
    out[0] = int32_t(hsum(acc0));
    out[1] = int32_t(hsum(acc1));
}

const Kernels kSse2 = {
    "sse2",
    ssd_sse2,
    nearest_sse2,
    dot_sse2,
    dot2_sse2,
    detail::prepare_query_portable,
    detail::descend_with<dot2_sse2, detail::prepare_query_portable>,
    detail::rank_candidates_portable,
    detail::lowest_ranked_portable,
    detail::window_ssd_sse2,
    detail::gram_i16_simd<detail::Sse2Lanes>,
    detail::project_pairs_simd<detail::Sse2Lanes>,
    detail::matvec_i32_portable,
    detail::packed_ssd_sse2,
    detail::packed_differences_sse2,
};

}  // namespace

const Kernels* sse2_kernels() { return &kSse2; }

}  // namespace vqtex::dsp
#else
namespace vqtex::dsp {
const Kernels* sse2_kernels() { return nullptr; }
}  // namespace vqtex::dsp
#endif
