// ssd_scalar.cpp - the reference distance kernels: plain C++, the definition
// of what every SIMD version must reproduce bit for bit.
#include "dsp/descent.hpp"
#include "dsp/dsp.hpp"
#include "dsp/linear_kernels.hpp"
#include "dsp/packed_pixels.hpp"

namespace vqtex::dsp {
namespace {

uint32_t ssd_scalar(const uint8_t* a, const uint8_t* b, std::size_t n) { return ssd_bytes(a, b, n); }

uint32_t nearest_scalar(const uint8_t* query, const uint8_t* rows, std::size_t stride,
                        std::size_t n, std::size_t count, uint32_t* best_distance) {
    uint32_t best = *best_distance;
    uint32_t best_index = UINT32_MAX;
    for (std::size_t r = 0; r < count; ++r) {
        const uint8_t* row = rows + r * stride;
        // Partial distances only grow, so a row can be abandoned as soon as it
        // reaches the best so far; this changes no result.
        uint32_t sum = 0;
        std::size_t i = 0;
        for (; i < n && sum < best; i += kVectorAlign) {
            for (std::size_t k = 0; k < kVectorAlign; ++k) {
                const int d = int(query[i + k]) - int(row[i + k]);
                sum += uint32_t(d * d);
            }
        }
        if (i >= n && sum < best) {
            best = sum;
            best_index = uint32_t(r);
        }
    }
    *best_distance = best;
    return best_index;
}

int32_t dot_scalar(const uint8_t* a, const int16_t* w, std::size_t n) {
    int32_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += int32_t(a[i]) * int32_t(w[i]);
    return sum;
}

VQTEX_DSP_INLINE void dot2_scalar(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out) {
    int32_t first = 0, second = 0;
    for (std::size_t i = 0; i < n; ++i) {
        first += int32_t(query[i]) * int32_t(pair[i]);
        second += int32_t(query[i]) * int32_t(pair[n + i]);
    }
    out[0] = first;
    out[1] = second;
}

// The definition of Kernels::window_ssd.
uint32_t window_ssd_scalar(const int16_t* query, const int16_t* example, std::ptrdiff_t tap_step,
                           std::ptrdiff_t row_step, int side, uint32_t bound) {
    uint32_t total = 0;
    for (int r = 0; r < side; ++r) {
        const int16_t* row = example + r * row_step;
        for (int c = 0; c < side; ++c, query += kWindowTapValues)
            for (int i = 0; i < kWindowTapValues; ++i) {
                const int32_t d = int32_t(row[c * tap_step + i]) - query[i];
                total += uint32_t(d * d);
            }
        if (total > bound) return total;
    }
    return total;
}

const Kernels kScalar = {
    "scalar",
    ssd_scalar,
    nearest_scalar,
    dot_scalar,
    dot2_scalar,
    detail::prepare_query_portable,
    detail::descend_with<dot2_scalar, detail::prepare_query_portable>,
    detail::rank_candidates_portable,
    detail::lowest_ranked_portable,
    window_ssd_scalar,
    detail::gram_i16_portable,
    detail::project_pairs_portable,
    detail::matvec_i32_portable,
    detail::packed_ssd_portable,
    detail::packed_differences_portable,
};

}  // namespace

const Kernels& scalar_kernels() { return kScalar; }

}  // namespace vqtex::dsp
