// ssd_avx2.cpp - AVX2 distance kernels, compiled with -mavx2 and only called
// after the dispatcher has seen AVX2 on the CPU. Bit-identical to the scalar
// kernels.
#include "dsp/descent.hpp"
#include "dsp/dsp.hpp"
#include "dsp/linear_kernels.hpp"

#if defined(__AVX2__) && !defined(VQTEX_SCALAR_ONLY)
#include "dsp/linear_kernels_simd.hpp"
#include "dsp/packed_pixels_sse2.hpp"
#include "dsp/window_ssd.hpp"
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

VQTEX_DSP_INLINE void dot2_avx2(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
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

// The low 64 bits of a * b per lane (AVX2 has only 32x32->64 multiplies).
inline __m256i mul64(__m256i a, __m256i b) {
    const __m256i low = _mm256_mul_epu32(a, b);
    const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), b),
                                           _mm256_mul_epu32(a, _mm256_srli_epi64(b, 32)));
    return _mm256_add_epi64(low, _mm256_slli_epi64(cross, 32));
}

// rank_hash of four keys, given key * 0x9E3779B97F4A7C15 for each (a
// running sum over consecutive keys: one multiply fewer).
inline __m256i rank_hash4_mixed(__m256i salt, __m256i key_times_golden) {
    __m256i z = _mm256_xor_si256(salt, key_times_golden);
    z = mul64(_mm256_xor_si256(z, _mm256_srli_epi64(z, 30)), _mm256_set1_epi64x(int64_t(kMixMultiplier1)));
    z = mul64(_mm256_xor_si256(z, _mm256_srli_epi64(z, 27)), _mm256_set1_epi64x(int64_t(kMixMultiplier2)));
    return _mm256_xor_si256(z, _mm256_srli_epi64(z, 31));
}

uint64_t rank_candidates_avx2(uint64_t salt, uint32_t count, uint64_t* ranks) {
    const __m256i salt4 = _mm256_set1_epi64x(int64_t(salt));
    constexpr uint64_t kGolden = kGoldenGamma;
    __m256i mixed = _mm256_set_epi64x(int64_t(3 * kGolden), int64_t(2 * kGolden), int64_t(kGolden), 0);
    const __m256i step = _mm256_set1_epi64x(int64_t(4 * kGolden));
    for (uint32_t base = 0; base < count; base += 4) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(ranks + base), rank_hash4_mixed(salt4, mixed));
        mixed = _mm256_add_epi64(mixed, step);
    }
    return detail::record_mask_portable(ranks, count);
}

uint32_t lowest_ranked_avx2(const uint64_t* ranks, uint32_t n, uint64_t allowed) {
    if (n < 64) allowed &= (uint64_t(1) << n) - 1;
    const __m256i none = _mm256_set1_epi64x(-1);
    const __m256i sign = _mm256_set1_epi64x(INT64_MIN);
    const __m256i lane_bit = _mm256_set_epi64x(8, 4, 2, 1);
    // The allowed lanes of four candidates as a vector mask, and their ranks
    // with the others as all ones (masked loads read nothing else).
    auto lanes_at = [&](uint32_t base) {
        const __m256i bits = _mm256_set1_epi64x(int64_t((allowed >> base) & 15));
        return _mm256_cmpeq_epi64(_mm256_and_si256(bits, lane_bit), lane_bit);
    };
    auto ranks_at = [&](uint32_t base, __m256i ok) {
        const __m256i loaded = _mm256_maskload_epi64(reinterpret_cast<const long long*>(ranks + base), ok);
        return _mm256_blendv_epi8(none, loaded, ok);
    };
    __m256i low = none;
    for (uint32_t base = 0; base < n; base += 4) {
        const __m256i rank = ranks_at(base, lanes_at(base));
        // Unsigned rank < low, through the signed compare.
        const __m256i lower = _mm256_cmpgt_epi64(_mm256_xor_si256(low, sign), _mm256_xor_si256(rank, sign));
        low = _mm256_blendv_epi8(low, rank, lower);
    }
    alignas(32) uint64_t lane_low[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane_low), low);
    uint64_t lowest = lane_low[0];
    for (int lane = 1; lane < 4; ++lane) lowest = lane_low[lane] < lowest ? lane_low[lane] : lowest;
    const __m256i target = _mm256_set1_epi64x(int64_t(lowest));
    uint64_t at_lowest = 0;
    for (uint32_t base = 0; base < n; base += 4) {
        const __m256i ok = lanes_at(base);
        const __m256i hit = _mm256_and_si256(ok, _mm256_cmpeq_epi64(ranks_at(base, ok), target));
        at_lowest |= uint64_t(_mm256_movemask_pd(_mm256_castsi256_pd(hit))) << base;
    }
    return uint32_t(__builtin_ctzll(at_lowest));
}

const Kernels kAvx2 = {
    "avx2",
    ssd_avx2,
    nearest_avx2,
    dot_avx2,
    dot2_avx2,
    detail::prepare_query_portable,
    detail::descend_with<dot2_avx2, detail::prepare_query_portable>,
    rank_candidates_avx2,
    lowest_ranked_avx2,
    detail::window_ssd_sse2,
    detail::gram_i16_simd<detail::Avx2Lanes>,
    detail::project_pairs_simd<detail::Avx2Lanes>,
    detail::matvec_i32_simd<detail::Avx2Matvec>,
    detail::packed_ssd_sse2,
    detail::packed_differences_sse2,
};

}  // namespace

const Kernels* avx2_kernels() { return &kAvx2; }

}  // namespace vqtex::dsp
#else
namespace vqtex::dsp {
const Kernels* avx2_kernels() { return nullptr; }
}  // namespace vqtex::dsp
#endif
