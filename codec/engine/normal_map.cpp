// normal_map.cpp - normal maps back to unit length (see normal_map.hpp).
#include "engine/normal_map.hpp"

#include <algorithm>
#include <cstdint>

#include "common/parallel.hpp"

namespace vqtex {
namespace {

// floor(sqrt(n)) for n < 2^64.
uint64_t isqrt64(uint64_t n) {
    uint64_t r = 0;
    for (uint64_t bit = uint64_t(1) << 62; bit != 0; bit >>= 2) {
        if (n >= r + bit) {
            n -= r + bit;
            r = (r >> 1) + bit;
        } else {
            r >>= 1;
        }
    }
    return r;
}

template <typename T>
void renormalise(BasicImage<T>& image, int64_t top, int threads) {
    if (image.channels < 3) return;
    const std::size_t ch = std::size_t(image.channels), n = image.pixel_count();
    parallel_for(threads, n, 4096, [&](std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
            T* p = image.pixels.data() + i * ch;
            int64_t a[3];
            uint64_t length2 = 0;
            for (int c = 0; c < 3; ++c) {
                a[c] = 2 * int64_t(p[c]) - top;
                length2 += uint64_t(a[c] * a[c]);
            }
            // r = floor(|a| * 2^16); each component in Q16 is a * 2^32 / r
            // (truncated toward zero), at most 2^16 in magnitude. |a|^2 is
            // below 3 * 2^24, so |a|^2 * 2^32 fits 64 bits.
            const int64_t r = int64_t(isqrt64(length2 << 32));
            for (int c = 0; c < 3; ++c) {
                const int64_t unit = a[c] * (int64_t(1) << 32) / r;
                // round(top (unit / 2^16 + 1) / 2), never negative.
                const int64_t v = (unit * top + top * (int64_t(1) << 16) + (int64_t(1) << 16)) >> 17;
                p[c] = T(std::clamp<int64_t>(v, 0, top));
            }
        }
    });
}

}  // namespace

void renormalise_normals(Image& image, int threads) { renormalise(image, 255, threads); }

void renormalise_normals(Image16& image, int bits, int threads) {
    renormalise(image, (int64_t(1) << bits) - 1, threads);
}

}  // namespace vqtex
