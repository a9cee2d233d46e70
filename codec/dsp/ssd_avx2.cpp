// ssd_avx2.cpp - AVX2 distance kernels, compiled with -mavx2 and only called
// after the dispatcher has seen AVX2 on the CPU. Bit-identical to the scalar
// kernels.
#include "dsp.hpp"

#if defined(__AVX2__) && !defined(VQTEX_SCALAR_ONLY)
#include <immintrin.h>

namespace vqtex::dsp {
namespace {

// 16 bytes widened to 16-bit lanes, squared and pair-summed to 8 x int32.
inline __m256i ssd16(const uint8_t* a, const uint8_t* b) {
    const __m256i va = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a)));
    const __m256i vb = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(b)));
    const __m256i d = _mm256_sub_epi16(va, vb);
    return _mm256_madd_epi16(d, d);
}

inline uint32_t hsum(__m256i v) {
    __m128i s = _mm_add_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(1, 0, 3, 2)));
    s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(2, 3, 0, 1)));
    return uint32_t(_mm_cvtsi128_si32(s));
}

uint32_t ssd_avx2(const uint8_t* a, const uint8_t* b, std::size_t n) {
    __m256i acc0 = _mm256_setzero_si256();
    __m256i acc1 = _mm256_setzero_si256();
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        acc0 = _mm256_add_epi32(acc0, ssd16(a + i, b + i));
        acc1 = _mm256_add_epi32(acc1, ssd16(a + i + 16, b + i + 16));
    }
    if (i < n) acc0 = _mm256_add_epi32(acc0, ssd16(a + i, b + i));
    return hsum(_mm256_add_epi32(acc0, acc1));
}

uint32_t nearest_avx2(const uint8_t* query, const uint8_t* rows, std::size_t stride,
                      std::size_t n, std::size_t count, uint32_t* best_distance) {
    uint32_t best = *best_distance;
    uint32_t best_index = UINT32_MAX;
    for (std::size_t r = 0; r < count; ++r) {
        const uint8_t* row = rows + r * stride;
        __m256i acc = _mm256_setzero_si256();
        std::size_t i = 0;
        uint32_t sum = 0;
        while (i < n) {
            const std::size_t end = (n - i > 64) ? i + 64 : n;
            for (; i < end; i += 16) acc = _mm256_add_epi32(acc, ssd16(query + i, row + i));
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

int32_t dot_avx2(const uint8_t* a, const int16_t* w, std::size_t n) {
    __m256i acc = _mm256_setzero_si256();
    for (std::size_t i = 0; i < n; i += 16) {
        const __m256i va = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i)));
        const __m256i vw = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(w + i));
        acc = _mm256_add_epi32(acc, _mm256_madd_epi16(va, vw));
    }
    return int32_t(hsum(acc));
}

void ssd2_avx2(const uint8_t* query, const uint8_t* pair, std::size_t n, uint32_t* out) {
    __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256();
    for (std::size_t i = 0; i < n; i += 16) {
        const __m256i q = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(query + i)));
        const __m256i a = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + i)));
        const __m256i b = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + n + i)));
        const __m256i da = _mm256_sub_epi16(q, a), db = _mm256_sub_epi16(q, b);
        acc0 = _mm256_add_epi32(acc0, _mm256_madd_epi16(da, da));
        acc1 = _mm256_add_epi32(acc1, _mm256_madd_epi16(db, db));
    }
    // Both horizontal sums at once: lanes 0-3 from acc0, 4-7 from acc1.
    const __m256i h = _mm256_hadd_epi32(acc0, acc1);  // a01 a23 b01 b23 | a45 a67 b45 b67
    const __m128i s = _mm_add_epi32(_mm256_castsi256_si128(h), _mm256_extracti128_si256(h, 1));
    const __m128i t = _mm_hadd_epi32(s, s);  // a, b, a, b
    out[0] = uint32_t(_mm_cvtsi128_si32(t));
    out[1] = uint32_t(_mm_extract_epi32(t, 1));
}

void dot2_avx2(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
    __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256();
    for (std::size_t i = 0; i < n; i += 16) {
        const __m256i q = _mm256_cvtepi8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(query + i)));
        const __m256i a = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + i)));
        const __m256i b = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pair + n + i)));
        acc0 = _mm256_add_epi32(acc0, _mm256_madd_epi16(q, a));
        acc1 = _mm256_add_epi32(acc1, _mm256_madd_epi16(q, b));
    }
    out[0] = int32_t(hsum(acc0));
    out[1] = int32_t(hsum(acc1));
}

const Kernels kAvx2 = {"avx2", ssd_avx2, nearest_avx2, dot_avx2, ssd2_avx2, dot2_avx2};

}  // namespace

const Kernels* avx2_kernels() { return &kAvx2; }

}  // namespace vqtex::dsp
#else
namespace vqtex::dsp {
const Kernels* avx2_kernels() { return nullptr; }
}  // namespace vqtex::dsp
#endif
