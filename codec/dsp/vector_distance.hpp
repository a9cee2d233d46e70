// vector_distance.hpp - the squared distance between two appearance vectors
// (kWindowTapValues values of 16 bits; Lefebvre & Hoppe 2006 section 3),
// inline for the engine's loops that compare single vectors rather than
// windows (copy relocation's seam costs, Kwatra et al. 2003): a call
// through the kernel table would cost more than the arithmetic. SSE2 is part
// of every x86-64 CPU, so this needs no dispatch; elsewhere, the same sum
// in plain code. The differences must fit 16 bits, and the sum 31 bits.
#pragma once

#include <cstdint>

#include "dsp/dsp.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace vqtex::dsp {

// Internal linkage (static): a file compiled with AVX flags that included
// this must not lend its copy to the others (see descent.hpp).
static inline int32_t vector_distance(const int16_t* a, const int16_t* b) {
    static_assert(kWindowTapValues == 8, "one 128-bit register a vector");
#if defined(__SSE2__)
    const __m128i d = _mm_sub_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a)),
                                    _mm_loadu_si128(reinterpret_cast<const __m128i*>(b)));
    __m128i s = _mm_madd_epi16(d, d);
    s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(1, 0, 3, 2)));
    s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_cvtsi128_si32(s);
#else
    int32_t sum = 0;
    for (int i = 0; i < kWindowTapValues; ++i) {
        const int32_t t = int32_t(a[i]) - int32_t(b[i]);
        sum += t * t;
    }
    return sum;
#endif
}

}  // namespace vqtex::dsp
