// packed_pixels.hpp - the seam covers' colour comparisons (engine/
// seam_cover.cpp) on pixels packed in 32 bits: a pixel's channels in its
// bytes, from the lowest, and zeros after them, so that a pixel of 1 to 4
// channels is one load and its squared difference one sum over 4 bytes.
// The portable definitions (packed_pixels_sse2.hpp has the SSE2 forms).
// Exact integer sums, so every set gives the same values. Internal linkage
// for the reason given in descent.hpp.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vqtex::dsp::detail {
namespace {

inline uint32_t packed_difference(uint32_t a, uint32_t b) {
    uint32_t sum = 0;
    for (int q = 0; q < 32; q += 8) {
        const int d = int((a >> q) & 0xFF) - int((b >> q) & 0xFF);
        sum += uint32_t(d * d);
    }
    return sum;
}

inline uint32_t packed_at(const uint32_t* pixels, std::size_t width, uint32_t position) {
    return pixels[std::size_t(position >> 16) * width + std::size_t(position & 0xFFFF)];
}

// Kernels::packed_ssd: in runs of 8 samples, returned once a run ends at or
// above the bound.
uint64_t packed_ssd_portable(const uint32_t* pixels, const int32_t* offsets, const uint32_t* wanted,
                             std::size_t count, uint64_t bound) {
    uint64_t total = 0;
    for (std::size_t s = 0; s < count && total < bound;) {
        const std::size_t end = s + 8 < count ? s + 8 : count;
        uint32_t run = 0;
        for (; s < end; ++s) run += packed_difference(pixels[offsets[s]], wanted[s]);
        total += run;
    }
    return total;
}

void packed_differences_portable(const uint32_t* pixels, std::size_t width, const uint32_t* positions,
                                 const uint32_t* cover, std::size_t step, std::size_t count, uint32_t* out) {
    for (std::size_t c = 0; c < count; ++c)
        out[c] = packed_difference(packed_at(pixels, width, positions[c]), cover[c * step]);
}


}  // namespace
}  // namespace vqtex::dsp::detail
