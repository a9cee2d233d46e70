// fill_order.cpp - spiral fill order for constrained synthesis (paper
// section 5.1).
#include "fill/fill_order.hpp"

#include <algorithm>
#include <cstddef>

#include "common/error.hpp"

namespace vqtex {
namespace {

// Cross products of centroid-relative positions need more than 64 bits.
__extension__ typedef __int128 int128;

constexpr uint32_t kUnreached = UINT32_MAX;

// Chessboard distance of every pixel to fill from the nearest pixel not to
// fill, by breadth-first search from the known pixels (8-neighbourhood).
std::vector<uint32_t> ring_numbers(int width, int height, const std::vector<uint8_t>& fill) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<uint32_t> ring(n, kUnreached);
    std::vector<uint32_t> frontier, next;
    for (std::size_t i = 0; i < n; ++i)
        if (!fill[i]) ring[i] = 0, frontier.push_back(uint32_t(i));
    for (uint32_t r = 1; !frontier.empty(); ++r) {
        next.clear();
        for (const uint32_t i : frontier) {
            const int x = int(i % uint32_t(width)), y = int(i / uint32_t(width));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                    const std::size_t j = std::size_t(ny) * std::size_t(width) + std::size_t(nx);
                    if (ring[j] != kUnreached) continue;
                    ring[j] = r;
                    next.push_back(uint32_t(j));
                }
        }
        frontier.swap(next);
    }
    return ring;
}

// 8-connected components of the pixels to fill, numbered in raster order of
// their first pixel; -1 elsewhere.
std::vector<int32_t> hole_labels(int width, int height, const std::vector<uint8_t>& fill,
                                 int32_t& count) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<int32_t> label(n, -1);
    std::vector<uint32_t> stack;
    count = 0;
    for (std::size_t start = 0; start < n; ++start) {
        if (!fill[start] || label[start] >= 0) continue;
        label[start] = count;
        stack.assign(1, uint32_t(start));
        while (!stack.empty()) {
            const uint32_t i = stack.back();
            stack.pop_back();
            const int x = int(i % uint32_t(width)), y = int(i / uint32_t(width));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                    const std::size_t j = std::size_t(ny) * std::size_t(width) + std::size_t(nx);
                    if (!fill[j] || label[j] >= 0) continue;
                    label[j] = count;
                    stack.push_back(uint32_t(j));
                }
        }
        ++count;
    }
    return label;
}

struct Visit {
    uint32_t ring;
    int32_t hole;
    // Position relative to the hole's centroid, scaled by the hole's pixel
    // count so that it is an exact integer.
    int64_t dx, dy;
    uint32_t index;
};

// Clockwise on screen (y down) from +x: the lower half-plane (dy > 0, or
// dy == 0 with dx > 0) comes first, then the upper one.
int half_plane(const Visit& v) { return (v.dy > 0 || (v.dy == 0 && v.dx > 0)) ? 0 : 1; }

bool spiral_before(const Visit& a, const Visit& b) {
    if (a.ring != b.ring) return a.ring < b.ring;
    if (a.hole != b.hole) return a.hole < b.hole;
    const bool a_centre = a.dx == 0 && a.dy == 0, b_centre = b.dx == 0 && b.dy == 0;
    if (a_centre != b_centre) return a_centre;
    if (!a_centre) {
        const int ha = half_plane(a), hb = half_plane(b);
        if (ha != hb) return ha < hb;
        const int128 cross = int128(a.dx) * b.dy - int128(a.dy) * b.dx;
        if (cross != 0) return cross > 0;
        const int128 ra = int128(a.dx) * a.dx + int128(a.dy) * a.dy;
        const int128 rb = int128(b.dx) * b.dx + int128(b.dy) * b.dy;
        if (ra != rb) return ra < rb;
    }
    return a.index < b.index;
}

}  // namespace

std::vector<uint32_t> spiral_order(int width, int height, const std::vector<uint8_t>& fill) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    if (fill.size() != n) fail(VQTEX_ERROR_INTERNAL, "fill mask size does not match the image");
    const std::vector<uint32_t> ring = ring_numbers(width, height, fill);
    int32_t holes = 0;
    const std::vector<int32_t> label = hole_labels(width, height, fill, holes);
    std::vector<int64_t> sum_x(std::size_t(holes), 0), sum_y(std::size_t(holes), 0),
        count(std::size_t(holes), 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (label[i] < 0) continue;
        if (ring[i] == kUnreached)
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "the region to fill covers the whole image: there is no known pixel to continue from");
        const std::size_t h = std::size_t(label[i]);
        sum_x[h] += int64_t(i % std::size_t(width));
        sum_y[h] += int64_t(i / std::size_t(width));
        ++count[h];
    }
    std::vector<Visit> visits;
    for (std::size_t i = 0; i < n; ++i) {
        if (label[i] < 0) continue;
        const std::size_t h = std::size_t(label[i]);
        const int64_t x = int64_t(i % std::size_t(width)), y = int64_t(i / std::size_t(width));
        visits.push_back({ring[i], label[i], x * count[h] - sum_x[h], y * count[h] - sum_y[h],
                          uint32_t(i)});
    }
    std::sort(visits.begin(), visits.end(), spiral_before);
    std::vector<uint32_t> order;
    order.reserve(visits.size());
    for (const Visit& v : visits) order.push_back(v.index);
    return order;
}

std::vector<uint32_t> raster_order(int width, int height, const std::vector<uint8_t>& fill) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    if (fill.size() != n) fail(VQTEX_ERROR_INTERNAL, "fill mask size does not match the image");
    std::vector<uint32_t> order;
    for (std::size_t i = 0; i < n; ++i)
        if (fill[i]) order.push_back(uint32_t(i));
    return order;
}

}  // namespace vqtex
