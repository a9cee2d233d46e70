// linear_kernels.hpp - the integer linear algebra of the appearance space
// (Lefebvre & Hoppe 2006, section 3: a PCA of the example's windows and the
// projection of every window on its axes; engine/appearance.cpp) as kernel
// templates. Plain loops: the definitions, which the scalar set (and the
// SSE2 set for the matrix-vector product) uses as they are and the wider
// sets' forms in linear_kernels_simd.hpp must match. All sums are exact
// integers modulo a power of two, so every set gives the same values.
// Internal linkage for the reason given in descent.hpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "dsp/dsp.hpp"

namespace vqtex::dsp::detail {
namespace {

inline uint32_t dot_i16_portable(const int16_t* a, const int16_t* b, std::size_t n) {
    uint32_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += uint32_t(int32_t(a[i]) * int32_t(b[i]));
    return sum;
}

// Kernels::gram_i16: the definition, a dot product per entry.
inline void gram_i16_portable(const int16_t* columns, std::size_t dims, std::size_t count, std::size_t first,
                              std::size_t last, uint32_t* products) {
    for (std::size_t i = first; i < last; ++i)
        for (std::size_t j = i; j < dims; ++j)
            products[i * dims + j] = dot_i16_portable(columns + i * count, columns + j * count, count);
}

// Kernels::project_pairs for pixels [begin, end): the definition, and the
// wider sets' tail of fewer pixels than a register holds.
inline void project_pairs_range(const int16_t* const* rows, const int32_t* weights, std::size_t count, std::size_t begin,
                         std::size_t end, const int32_t* offset, int32_t limit, int16_t* out) {
    for (std::size_t i = begin; i < end; ++i)
        for (int a = 0; a < kWindowTapValues; ++a) {
            uint32_t sum = 0;
            for (std::size_t e = 0; e < count; ++e) {
                const int32_t w = weights[e * kWindowTapValues + std::size_t(a)];
                const int32_t low = int16_t(uint16_t(uint32_t(w))), high = int16_t(uint16_t(uint32_t(w) >> 16));
                sum += uint32_t(low * int32_t(rows[e][2 * i])) + uint32_t(high * int32_t(rows[e][2 * i + 1]));
            }
            const int64_t v = (int64_t(int32_t(sum)) - offset[a] + (1 << 14)) >> 15;
            out[i * kWindowTapValues + std::size_t(a)] = int16_t(v < -limit ? -limit : v > limit ? limit : v);
        }
}

inline void project_pairs_portable(const int16_t* const* rows, const int32_t* weights, std::size_t count, std::size_t n,
                            const int32_t* offset, int32_t limit, int16_t* out) {
    project_pairs_range(rows, weights, count, 0, n, offset, limit, out);
}

// Kernels::matvec_i32: the definition (row by row, so that the inner
// loop runs along memory).
inline void matvec_i32_portable(const int32_t* m, const int32_t* v, std::size_t n, int64_t* out) {
    for (std::size_t i = 0; i < n; ++i) out[i] = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const int64_t factor = v[j];
        const int32_t* row = m + j * n;
        for (std::size_t i = 0; i < n; ++i) out[i] = int64_t(uint64_t(out[i]) + uint64_t(int64_t(row[i]) * factor));
    }
}

}  // namespace
}  // namespace vqtex::dsp::detail
