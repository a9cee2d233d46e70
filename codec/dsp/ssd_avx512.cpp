// ssd_avx512.cpp - AVX-512 (F+BW+DQ) distance kernels, compiled with its own
// flags and only called when the CPU reports AVX-512BW and DQ. Bit-identical to the
// scalar kernels.
#include "dsp/descent.hpp"
#include "dsp/dsp.hpp"
#include "dsp/linear_kernels.hpp"

#if defined(__AVX512BW__) && defined(__AVX512DQ__) && !defined(VQTEX_SCALAR_ONLY)
#include "dsp/packed_pixels_sse2.hpp"
#include "dsp/window_ssd.hpp"
// GCC 12's own AVX-512 reduction helpers trip its uninitialised-value
// warnings (they start from _mm256_undefined); the code is correct.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

#include "dsp/linear_kernels_simd.hpp"

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

VQTEX_DSP_INLINE void dot2_avx512(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
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

// rank_hash of eight consecutive keys, given key * 0x9E3779B97F4A7C15 for
// each: the first multiply of the hash, which is a running sum over
// consecutive keys, so one multiply fewer per vector.
inline __m512i rank_hash8_mixed(__m512i salt, __m512i key_times_golden) {
    __m512i z = _mm512_xor_si512(salt, key_times_golden);
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)),
                           _mm512_set1_epi64(int64_t(kMixMultiplier1)));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)),
                           _mm512_set1_epi64(int64_t(kMixMultiplier2)));
    return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

uint64_t rank_candidates_avx512(uint64_t salt, uint32_t count, uint64_t* ranks) {
    const __m512i salt8 = _mm512_set1_epi64(int64_t(salt));
    constexpr uint64_t kGolden = kGoldenGamma;
    __m512i mixed = _mm512_set_epi64(int64_t(7 * kGolden), int64_t(6 * kGolden), int64_t(5 * kGolden),
                                     int64_t(4 * kGolden), int64_t(3 * kGolden), int64_t(2 * kGolden),
                                     int64_t(kGolden), 0);
    const __m512i step = _mm512_set1_epi64(int64_t(8 * kGolden));
    const __m512i none = _mm512_set1_epi64(-1);
    // Records from prefix minima: three shift-and-min steps per vector, the
    // minimum so far carried across vectors. A rank is a record when it is
    // below the minimum of everything before it (ties keep the earlier).
    __m512i carry = none;
    uint64_t records = 1;
    for (uint32_t base = 0; base < count; base += 8) {
        const __m512i rank = rank_hash8_mixed(salt8, mixed);
        mixed = _mm512_add_epi64(mixed, step);
        _mm512_storeu_si512(ranks + base, rank);
        __m512i prefix = _mm512_min_epu64(rank, _mm512_alignr_epi64(rank, none, 7));
        prefix = _mm512_min_epu64(prefix, _mm512_alignr_epi64(prefix, none, 6));
        prefix = _mm512_min_epu64(prefix, _mm512_alignr_epi64(prefix, none, 4));
        prefix = _mm512_min_epu64(prefix, carry);
        const __m512i before = _mm512_alignr_epi64(prefix, carry, 7);  // minimum of all earlier ranks
        records |= uint64_t(_mm512_cmplt_epu64_mask(rank, before)) << base;
        carry = _mm512_permutexvar_epi64(_mm512_set1_epi64(7), prefix);
    }
    return records & (count < 64 ? (uint64_t(1) << count) - 1 : ~uint64_t(0));
}

uint32_t lowest_ranked_avx512(const uint64_t* ranks, uint32_t n, uint64_t allowed) {
    if (n < 64) allowed &= (uint64_t(1) << n) - 1;
    // Candidates not allowed read as all ones, and masked loads read nothing
    // else: the lowest rank, then the first allowed index holding it.
    const __m512i none = _mm512_set1_epi64(-1);
    __m512i low = none;
    for (uint32_t base = 0; base < n; base += 8)
        low = _mm512_min_epu64(low, _mm512_mask_loadu_epi64(none, __mmask8(allowed >> base), ranks + base));
    const __m512i lowest = _mm512_set1_epi64(int64_t(_mm512_reduce_min_epu64(low)));
    uint64_t at_lowest = 0;
    for (uint32_t base = 0; base < n; base += 8) {
        const __mmask8 lanes = __mmask8(allowed >> base);
        at_lowest |= uint64_t(_mm512_mask_cmpeq_epu64_mask(lanes, _mm512_maskz_loadu_epi64(lanes, ranks + base), lowest))
                     << base;
    }
    return uint32_t(__builtin_ctzll(at_lowest));
}

const Kernels kAvx512 = {
    "avx512",
    ssd_avx512,
    nearest_avx512,
    dot_avx512,
    dot2_avx512,
    detail::prepare_query_portable,
    detail::descend_with<dot2_avx512, detail::prepare_query_portable>,
    rank_candidates_avx512,
    lowest_ranked_avx512,
    detail::window_ssd_sse2,
    detail::gram_i16_simd<detail::Avx512Lanes>,
    detail::project_pairs_simd<detail::Avx512Lanes>,
    detail::matvec_i32_simd<detail::Avx512Matvec>,
    detail::packed_ssd_sse2,
    detail::packed_differences_sse2,
};

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
