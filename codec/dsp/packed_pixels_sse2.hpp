// packed_pixels_sse2.hpp - the SSE2 forms of packed_pixels.hpp's kernels,
// which every x86 set uses (compiled with its own flags): the pixels are
// read from scattered places, and AVX2's gather, where measured, was slower
// than four scalar loads. Internal linkage for the reason given in
// descent.hpp.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>

#include "dsp/packed_pixels.hpp"

namespace vqtex::dsp::detail {
namespace {

// The absolute differences of the bytes of a and b, widened to 16 bits.
inline void packed_distance_sse2(__m128i a, __m128i b, __m128i& low, __m128i& high) {
    const __m128i zero = _mm_setzero_si128();
    const __m128i d = _mm_sub_epi8(_mm_max_epu8(a, b), _mm_min_epu8(a, b));
    low = _mm_unpacklo_epi8(d, zero);
    high = _mm_unpackhi_epi8(d, zero);
}

// Kernels::packed_ssd: runs of 8 samples, the bound looked at after each.
uint64_t packed_ssd_sse2(const uint32_t* pixels, const int32_t* offsets, const uint32_t* wanted,
                         std::size_t count, uint64_t bound) {
    uint64_t total = 0;
    std::size_t s = 0;
    for (; s + 8 <= count; s += 8) {
        const int32_t* o = offsets + s;
        const __m128i a0 = _mm_setr_epi32(int(pixels[o[0]]), int(pixels[o[1]]), int(pixels[o[2]]), int(pixels[o[3]]));
        const __m128i a1 = _mm_setr_epi32(int(pixels[o[4]]), int(pixels[o[5]]), int(pixels[o[6]]), int(pixels[o[7]]));
        __m128i l0, h0, l1, h1;
        packed_distance_sse2(a0, _mm_loadu_si128(reinterpret_cast<const __m128i*>(wanted + s)), l0, h0);
        packed_distance_sse2(a1, _mm_loadu_si128(reinterpret_cast<const __m128i*>(wanted + s + 4)), l1, h1);
        __m128i acc = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(l0, l0), _mm_madd_epi16(h0, h0)),
                                    _mm_add_epi32(_mm_madd_epi16(l1, l1), _mm_madd_epi16(h1, h1)));
        acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(1, 0, 3, 2)));
        acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(2, 3, 0, 1)));
        total += uint32_t(_mm_cvtsi128_si32(acc));
        if (total >= bound) return total;
    }
    if (s == count) return total;
    return total + packed_ssd_portable(pixels, offsets + s, wanted + s, count - s, bound - total);
}

// Kernels::packed_differences: 4 pixels at a time.
void packed_differences_sse2(const uint32_t* pixels, std::size_t width, const uint32_t* positions,
                             const uint32_t* cover, std::size_t step, std::size_t count, uint32_t* out) {
    std::size_t c = 0;
    for (; c + 4 <= count; c += 4) {
        const uint32_t* p = positions + c;
        const __m128i a = _mm_setr_epi32(int(packed_at(pixels, width, p[0])), int(packed_at(pixels, width, p[1])),
                                         int(packed_at(pixels, width, p[2])), int(packed_at(pixels, width, p[3])));
        const uint32_t* b = cover + c * step;
        __m128i low, high;
        packed_distance_sse2(a, _mm_setr_epi32(int(b[0]), int(b[step]), int(b[2 * step]), int(b[3 * step])), low,
                             high);
        // Per pixel two sums of two channels each: (0, 1) and (2, 3).
        const __m128 ml = _mm_castsi128_ps(_mm_madd_epi16(low, low));
        const __m128 mh = _mm_castsi128_ps(_mm_madd_epi16(high, high));
        const __m128i even = _mm_castps_si128(_mm_shuffle_ps(ml, mh, _MM_SHUFFLE(2, 0, 2, 0)));
        const __m128i odd = _mm_castps_si128(_mm_shuffle_ps(ml, mh, _MM_SHUFFLE(3, 1, 3, 1)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + c), _mm_add_epi32(even, odd));
    }
    packed_differences_portable(pixels, width, positions + c, cover + c * step, step, count - c, out + c);
}
}  // namespace
}  // namespace vqtex::dsp::detail
