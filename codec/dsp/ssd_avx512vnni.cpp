// ssd_avx512vnni.cpp - the AVX-512 kernels plus a dot2 that uses VNNI's
// unsigned-by-signed byte dot product (vpdpbusd): 64 byte products summed
// into 16 lanes per instruction, exactly. Compiled with its own flags and
// only called when the CPU reports AVX-512 VNNI; bit-identical to scalar.
#include "descent.hpp"
#include "dsp.hpp"

#if defined(__AVX512VNNI__) && defined(__AVX512BW__) && defined(__AVX512DQ__) && !defined(VQTEX_SCALAR_ONLY)
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

namespace vqtex::dsp {
namespace {

VQTEX_DSP_INLINE void dot2_avx512vnni(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
    __m512i acc0 = _mm512_setzero_si512(), acc1 = _mm512_setzero_si512();
    std::size_t i = 0;
    for (; i + 64 <= n; i += 64) {
        const __m512i q = _mm512_loadu_si512(reinterpret_cast<const void*>(query + i));
        const __m512i a = _mm512_loadu_si512(reinterpret_cast<const void*>(pair + i));
        const __m512i b = _mm512_loadu_si512(reinterpret_cast<const void*>(pair + n + i));
        acc0 = _mm512_dpbusd_epi32(acc0, a, q);
        acc1 = _mm512_dpbusd_epi32(acc1, b, q);
    }
    if (i < n) {
        // The last 16 to 48 bytes: masked loads read nothing beyond n.
        const __mmask64 mask = (~uint64_t(0)) >> (64 - (n - i));
        const __m512i q = _mm512_maskz_loadu_epi8(mask, query + i);
        const __m512i a = _mm512_maskz_loadu_epi8(mask, pair + i);
        const __m512i b = _mm512_maskz_loadu_epi8(mask, pair + n + i);
        acc0 = _mm512_dpbusd_epi32(acc0, a, q);
        acc1 = _mm512_dpbusd_epi32(acc1, b, q);
    }
    out[0] = _mm512_reduce_add_epi32(acc0);
    out[1] = _mm512_reduce_add_epi32(acc1);
}

uint64_t descend_avx512vnni(const DescentTree& tree, const int8_t* signed_query, int64_t query_norm,
                            uint64_t start, uint64_t* pending, std::size_t* pending_count) {
    return detail::descend_tree(tree, signed_query, query_norm, start, pending, pending_count,
                                      dot2_avx512vnni);
}

Kernels make_vnni() {
    Kernels k = detail::avx512_base();
    k.name = "avx512vnni";
    k.dot2 = dot2_avx512vnni;
    k.descend = descend_avx512vnni;
    return k;
}

}  // namespace

const Kernels* avx512vnni_kernels() {
    static const Kernels k = make_vnni();
    return &k;
}

}  // namespace vqtex::dsp
#else
namespace vqtex::dsp {
const Kernels* avx512vnni_kernels() { return nullptr; }
}  // namespace vqtex::dsp
#endif
