// window_ssd.hpp - the coherent engine's neighbourhood distance (Lefebvre &
// Hoppe 2006's comparison of appearance-vector windows) as a kernel
// template. Every set that has SSE2 instantiates this one, compiled with its
// own flags (VEX-encoded under AVX2 and AVX-512): the window's taps are 8
// values of 16 bits, one 128-bit lane each, so wider registers would only
// add shuffles. Internal linkage for the reason given in descent.hpp.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>

#include "dsp/dsp.hpp"

namespace vqtex::dsp::detail {
namespace {

// Kernels::window_ssd with SSE2: per tap one subtract and one multiply-add
// of pairs; sums wrap modulo 2^32 exactly as the scalar definition's do.
uint32_t window_ssd_sse2(const int16_t* query, const int16_t* example, std::ptrdiff_t tap_step,
                         std::ptrdiff_t row_step, int side, uint32_t bound) {
    uint32_t total = 0;
    for (int r = 0; r < side; ++r) {
        __m128i acc = _mm_setzero_si128();
        const int16_t* row = example + r * row_step;
        for (int c = 0; c < side; ++c, query += kWindowTapValues) {
            const __m128i q = _mm_loadu_si128(reinterpret_cast<const __m128i*>(query));
            const __m128i e = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + c * tap_step));
            const __m128i d = _mm_sub_epi16(e, q);
            acc = _mm_add_epi32(acc, _mm_madd_epi16(d, d));
        }
        acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(1, 0, 3, 2)));
        acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(2, 3, 0, 1)));
        total += uint32_t(_mm_cvtsi128_si32(acc));
        if (total > bound) return total;
    }
    return total;
}

}  // namespace
}  // namespace vqtex::dsp::detail
