// coherent_torus.cpp - the cut of the coherent engine's output torus where
// its pixels change least (Lefebvre & Hoppe 2005's toroidal outputs). See
// coherent_torus.hpp.
#include "engine/coherent_torus.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "common/parallel.hpp"

namespace vqtex::coherent {
namespace {

// The first of the least of `across`, so that ties go the same way for
// every caller.
int first_least(const std::vector<int64_t>& across) {
    std::size_t at = 0;
    for (std::size_t i = 1; i < across.size(); ++i)
        if (across[i] < across[at]) at = i;
    return int(at);
}

// The sum of |a[i] - b[i]| over n samples.
template <typename T>
uint64_t sample_distance(const T* __restrict a, const T* __restrict b, std::size_t n) {
    uint64_t d = 0;
    for (std::size_t i = 0; i < n; ++i) d += uint32_t(std::abs(int(a[i]) - int(b[i])));
    return d;
}

// The bytes' sums in 32 bits (a row of at most 16384 x 4 bytes fits),
// which vectorise.
uint32_t byte_distance(const uint8_t* __restrict a, const uint8_t* __restrict b, std::size_t n) {
    uint32_t d = 0;
    for (std::size_t i = 0; i < n; ++i) d += uint32_t(std::abs(int(a[i]) - int(b[i])));
    return d;
}

// acc[i - first] += |row[i] - row[i - channels]| for i in [first, last).
template <typename T>
void add_steps(const T* __restrict row, std::size_t first, std::size_t last, std::size_t channels,
               uint32_t* __restrict acc) {
    for (std::size_t i = first; i < last; ++i) acc[i - first] += uint32_t(std::abs(int(row[i]) - int(row[i - channels])));
}

// One plane's sums into across_y (rows y0..y1) or a strip's into acc.
template <typename T>
uint64_t row_step(const TorusPlane& plane, int w, int h, std::size_t y) {
    const std::size_t samples = std::size_t(w) * std::size_t(plane.channels);
    const T* base = reinterpret_cast<const T*>(plane.pixels);
    const T* above = base + (y == 0 ? std::size_t(h - 1) : y - 1) * samples;
    if constexpr (sizeof(T) == 1)
        return byte_distance(above, base + y * samples, samples);
    else
        return sample_distance(above, base + y * samples, samples);
}

template <typename T>
void strip_steps(const TorusPlane& plane, int w, int h, int x0, int x1, std::vector<uint32_t>& acc) {
    const std::size_t ch = std::size_t(plane.channels), row_samples = std::size_t(w) * ch;
    const T* base = reinterpret_cast<const T*>(plane.pixels);
    for (int y = 0; y < h; ++y) {
        const T* row = base + std::size_t(y) * row_samples;
        // Column 0 steps from the last column (the wrap).
        if (x0 == 0)
            for (std::size_t c = 0; c < ch; ++c) acc[c] += uint32_t(std::abs(int(row[c]) - int(row[row_samples - ch + c])));
        add_steps(row, std::size_t(std::max(x0, 1)) * ch, std::size_t(x1) * ch, ch, acc.data() + (x0 == 0 ? ch : 0));
    }
}

// Cuts the w x h torus at `pixels` open at (ox, oy) in place: pixel (x, y)
// becomes the one at (x + ox, y + oy). Rows move along the cycles of the
// turn by oy, each copied once, turned by ox on the way, with one row held
// aside per cycle: no second image.
void roll_in_place(uint8_t* pixels, int w, int h, int channels, int ox, int oy) {
    const std::size_t pixel = std::size_t(channels), row_bytes = std::size_t(w) * pixel;
    const std::size_t head = std::size_t(ox) * pixel, tail = row_bytes - head;
    if (ox == 0 && oy == 0) return;
    const auto row = [&](int y) { return pixels + std::size_t(y) * row_bytes; };
    std::vector<uint8_t> held(row_bytes);
    int moved = 0;
    for (int start = 0; moved < h; ++start) {
        std::memcpy(held.data(), row(start), row_bytes);
        int y = start;
        for (;;) {
            const int from = (y + oy) % h;
            const uint8_t* src = from == start ? held.data() : row(from);
            std::memcpy(row(y), src + head, tail);
            std::memcpy(row(y) + tail, src, head);
            ++moved;
            if (from == start) break;
            y = from;
        }
    }
}

}  // namespace

// The sums are exact integers, so their order is free. They are taken on
// the bytes as they lie (a row against the one above; a row against itself
// a pixel on, in strips of columns), which vectorise: through the
// positions, a pixel at a time, they were 5% of a 512x512 decode.
void cut_torus(const std::vector<TorusPlane>& planes, int w, int h, int threads) {
    std::vector<int64_t> across_x(std::size_t(w), 0), across_y(std::size_t(h), 0);
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t y = y0; y < y1; ++y)
            for (const TorusPlane& plane : planes)
                if (plane.counted)
                    across_y[y] += int64_t(plane.sample_bytes == 2 ? row_step<uint16_t>(plane, w, h, y)
                                                               : row_step<uint8_t>(plane, w, h, y));
    });
    constexpr int kStrip = 256;
    parallel_for(threads, std::size_t((w + kStrip - 1) / kStrip), 1, [&](std::size_t s0, std::size_t s1) {
        const int x0 = int(s0) * kStrip, x1 = std::min(w, int(s1) * kStrip);
        std::vector<uint32_t> acc;  // per byte of the strip, a plane at a time
        for (const TorusPlane& plane : planes) {
            if (!plane.counted) continue;
            const std::size_t ch = std::size_t(plane.channels);
            acc.assign(std::size_t(x1 - x0) * ch, 0u);
            if (plane.sample_bytes == 2)
                strip_steps<uint16_t>(plane, w, h, x0, x1, acc);
            else
                strip_steps<uint8_t>(plane, w, h, x0, x1, acc);
            for (int x = x0; x < x1; ++x) {
                int64_t sum = 0;
                for (std::size_t c = 0; c < ch; ++c) sum += acc[std::size_t(x - x0) * ch + c];
                across_x[std::size_t(x)] += sum;
            }
        }
    });
    const int ox = first_least(across_x), oy = first_least(across_y);
    for (const TorusPlane& plane : planes)
        roll_in_place(plane.pixels, w, h, plane.channels * plane.sample_bytes, ox, oy);
}

}  // namespace vqtex::coherent
