// ssd_avx512.cpp - AVX-512 (F+BW) distance kernels, compiled with its own
// flags and only called when the CPU reports AVX-512BW. Bit-identical to the
// scalar kernels.
#include "dsp.hpp"

#if defined(__AVX512BW__) && !defined(VQTEX_SCALAR_ONLY)
// GCC 12's own AVX-512 reduction helpers trip its uninitialised-value
// warnings (they start from _mm256_undefined); the code is correct.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

namespace vqtex::dsp {
namespace {

// 32 bytes widened to 16-bit lanes, squared and pair-summed to 16 x int32.
inline __m512i ssd32(const uint8_t* a, const uint8_t* b) {
    const __m512i va = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a)));
    const __m512i vb = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(b)));
    const __m512i d = _mm512_sub_epi16(va, vb);
    return _mm512_madd_epi16(d, d);
}

// 16 bytes (the tail when n is an odd multiple of 16).
inline __m512i ssd16(const uint8_t* a, const uint8_t* b) {
    const __m256i va = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a)));
    const __m256i vb = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(b)));
    const __m256i d = _mm256_sub_epi16(va, vb);
    return _mm512_zextsi256_si512(_mm256_madd_epi16(d, d));
}

uint32_t ssd_avx512(const uint8_t* a, const uint8_t* b, std::size_t n) {
    __m512i acc = _mm512_setzero_si512();
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) acc = _mm512_add_epi32(acc, ssd32(a + i, b + i));
    if (i < n) acc = _mm512_add_epi32(acc, ssd16(a + i, b + i));
    return uint32_t(_mm512_reduce_add_epi32(acc));
}

uint32_t nearest_avx512(const uint8_t* query, const uint8_t* rows, std::size_t stride,
                        std::size_t n, std::size_t count, uint32_t* best_distance) {
    uint32_t best = *best_distance;
    uint32_t best_index = UINT32_MAX;
    for (std::size_t r = 0; r < count; ++r) {
        const uint8_t* row = rows + r * stride;
        __m512i acc = _mm512_setzero_si512();
        std::size_t i = 0;
        uint32_t sum = 0;
        while (i < n) {
            const std::size_t end = (n - i > 64) ? i + 64 : n;
            for (; i + 32 <= end; i += 32) acc = _mm512_add_epi32(acc, ssd32(query + i, row + i));
            if (i < end) {
                acc = _mm512_add_epi32(acc, ssd16(query + i, row + i));
                i += 16;
            }
            sum = uint32_t(_mm512_reduce_add_epi32(acc));
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

int32_t dot_avx512(const uint8_t* a, const int16_t* w, std::size_t n) {
    __m512i acc = _mm512_setzero_si512();
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        const __m512i va = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + i)));
        const __m512i vw = _mm512_loadu_si512(reinterpret_cast<const void*>(w + i));
        acc = _mm512_add_epi32(acc, _mm512_madd_epi16(va, vw));
    }
    if (i < n) {
        const __m256i va = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i)));
        const __m256i vw = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + i));
        acc = _mm512_add_epi32(acc, _mm512_zextsi256_si512(_mm256_madd_epi16(va, vw)));
    }
    return int32_t(_mm512_reduce_add_epi32(acc));
}

void ssd2_avx512(const uint8_t* query, const uint8_t* pair, std::size_t n, uint32_t* out) {
    __m512i acc0 = _mm512_setzero_si512(), acc1 = _mm512_setzero_si512();
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        const __m512i q = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(query + i)));
        const __m512i a = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(pair + i)));
        const __m512i b = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(pair + n + i)));
        const __m512i da = _mm512_sub_epi16(q, a), db = _mm512_sub_epi16(q, b);
        acc0 = _mm512_add_epi32(acc0, _mm512_madd_epi16(da, da));
        acc1 = _mm512_add_epi32(acc1, _mm512_madd_epi16(db, db));
    }
    if (i < n) {
        acc0 = _mm512_add_epi32(acc0, ssd16(query + i, pair + i));
        acc1 = _mm512_add_epi32(acc1, ssd16(query + i, pair + n + i));
    }
    out[0] = uint32_t(_mm512_reduce_add_epi32(acc0));
    out[1] = uint32_t(_mm512_reduce_add_epi32(acc1));
}

void dot2_avx512(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
    __m512i acc0 = _mm512_setzero_si512(), acc1 = _mm512_setzero_si512();
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        const __m512i q = _mm512_cvtepi8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(query + i)));
        const __m512i a = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(pair + i)));
        const __m512i b = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(pair + n + i)));
        acc0 = _mm512_add_epi32(acc0, _mm512_madd_epi16(q, a));
        acc1 = _mm512_add_epi32(acc1, _mm512_madd_epi16(q, b));
    }
    if (i < n) {
        const __m256i q = _mm256_cvtepi8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(query + i)));
        const __m256i a = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + i)));
        const __m256i b = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + n + i)));
        acc0 = _mm512_add_epi32(acc0, _mm512_zextsi256_si512(_mm256_madd_epi16(q, a)));
        acc1 = _mm512_add_epi32(acc1, _mm512_zextsi256_si512(_mm256_madd_epi16(q, b)));
    }
    out[0] = _mm512_reduce_add_epi32(acc0);
    out[1] = _mm512_reduce_add_epi32(acc1);
}

const Kernels kAvx512 = {"avx512", ssd_avx512, nearest_avx512, dot_avx512, ssd2_avx512, dot2_avx512};

}  // namespace

const Kernels* avx512_kernels() { return &kAvx512; }

namespace detail {
const Kernels& avx512_base() { return kAvx512; }
}  // namespace detail

}  // namespace vqtex::dsp
#else
namespace vqtex::dsp {
const Kernels* avx512_kernels() { return nullptr; }
}  // namespace vqtex::dsp
#endif
