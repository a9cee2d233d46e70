// copy_relocation.cpp - moving whole copies to where they fit the copies
// around them (see copy_relocation.hpp; docs/FORMAT.md §4.9).
#include "engine/copy_relocation.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "common/hash.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "dsp/vector_distance.hpp"
#include "engine/coherent_start.hpp"

namespace vqtex {
namespace {

// pixel_hash purpose of the candidate translations (the engine's other
// purposes are below 16).
constexpr int kRelocationPurpose = 50;

// The four neighbours a copy shares links with, in the order links are
// scored: right, left, down, up.
constexpr int kStepX[4] = {1, -1, 0, 0};
constexpr int kStepY[4] = {0, 0, 1, -1};

struct Link {
    uint32_t mine;   // the copy's position at the pixel
    uint32_t there;  // the neighbour's position
    uint32_t view;   // the neighbour's copy continued onto the pixel
    bool has_view;   // false where that falls off the example
    int8_t dx, dy;   // from the pixel to the neighbour
};

}  // namespace

void relocate_copies(const AppearanceSpace& space, int level, PositionMap& map, int candidates, uint64_t seed,
                     int threads) {
    const int w = map.width, h = map.height;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    if (candidates <= 0 || space.wraps || n < 2) return;
    const int ew = space.width, eh = space.height;
    const int s = space.levels[std::size_t(level)].spacing;
    const int16_t* features = space.levels[std::size_t(level)].features.data();
    std::vector<uint32_t>& pos = map.positions;
    // Position p moved by (dx, dy), when that stays inside the example.
    const auto moved = [&](uint32_t p, int dx, int dy, uint32_t& out) {
        const int x = position_x(p) + dx, y = position_y(p) + dy;
        if (x < 0 || y < 0 || x >= ew || y >= eh) return false;
        out = pack_position(x, y);
        return true;
    };
    // Vectors are clamped to +-kAppearanceClamp, so a distance fits 32 bits.
    static_assert(int64_t(kAppearanceDims) * (2 * kAppearanceClamp) * (2 * kAppearanceClamp) < (int64_t(1) << 31),
                  "an appearance distance must fit int32_t");
    static_assert(2 * kAppearanceClamp < 32768, "dsp::vector_distance takes differences of 16 bits");
    const auto distance = [&](uint32_t a, uint32_t b) {
        const int16_t* u = features + (std::size_t(position_y(a)) * std::size_t(ew) + position_x(a)) * kAppearanceDims;
        const int16_t* v = features + (std::size_t(position_y(b)) * std::size_t(ew) + position_x(b)) * kAppearanceDims;
        return int64_t(dsp::vector_distance(u, v));
    };
    const auto neighbour = [&](std::size_t i, int k) {
        const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
        return std::size_t(Image::wrap(y + kStepY[k], h)) * std::size_t(w) + std::size_t(Image::wrap(x + kStepX[k], w));
    };

    // Copies: union-find over the links whose positions continue each other,
    // the smaller index the root, so a copy's label is its first pixel in
    // raster order.
    std::vector<uint32_t> label(n);
    for (std::size_t i = 0; i < n; ++i) label[i] = uint32_t(i);
    const auto root = [&](uint32_t a) {
        while (label[a] != a) {
            label[a] = label[label[a]];
            a = label[a];
        }
        return a;
    };
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 4; k += 2) {  // right and down
            const std::size_t j = neighbour(i, k);
            uint32_t next;
            if (j == i || !moved(pos[i], kStepX[k] * s, kStepY[k] * s, next) || pos[j] != next) continue;
            const uint32_t a = root(uint32_t(i)), b = root(uint32_t(j));
            if (a != b) label[std::max(a, b)] = std::min(a, b);
        }
    for (std::size_t i = 0; i < n; ++i) label[i] = root(uint32_t(i));

    // Each copy's pixels in raster order (a counting sort by label).
    std::vector<uint32_t> start(n + 1, 0), order(n);
    for (std::size_t i = 0; i < n; ++i) ++start[label[i] + 1];
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    {
        std::vector<uint32_t> next(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < n; ++i) order[next[label[i]]++] = uint32_t(i);
    }
    std::vector<uint32_t> copies;
    for (std::size_t i = 0; i < n; ++i)
        if (label[i] == i) copies.push_back(uint32_t(i));

    // Every copy is scored against the map as it is, so copies are
    // independent and go on the threads; all are moved afterwards. (One
    // after another, each seeing the moves before it, gave the same scores
    // for five times the time, measured in
    // docs/studies/2026-11-24-copy-relocation.md.)
    std::vector<std::pair<int, int>> move(copies.size(), {0, 0});
    parallel_for(threads, copies.size(), 4, [&](std::size_t c0, std::size_t c1) {
        std::vector<Link> links;
        for (std::size_t c = c0; c < c1; ++c) {
            const uint32_t first = copies[c];
            const uint32_t* pixels = order.data() + start[first];
            const std::size_t count = start[first + 1] - start[first];
            // A copy covering half the level or more stays: the others are
            // moved to fit it.
            if (2 * count >= n) continue;
            int min_x = ew, min_y = eh, max_x = 0, max_y = 0;
            for (std::size_t q = 0; q < count; ++q) {
                const uint32_t p = pos[pixels[q]];
                min_x = std::min(min_x, position_x(p));
                max_x = std::max(max_x, position_x(p));
                min_y = std::min(min_y, position_y(p));
                max_y = std::max(max_y, position_y(p));
            }
            links.clear();
            for (std::size_t q = 0; q < count; ++q)
                for (int k = 0; k < 4; ++k) {
                    const std::size_t j = neighbour(pixels[q], k);
                    if (label[j] == first) continue;
                    Link link{pos[pixels[q]], pos[j], 0, false, int8_t(kStepX[k]), int8_t(kStepY[k])};
                    link.has_view = moved(pos[j], -kStepX[k] * s, -kStepY[k] * s, link.view);
                    links.push_back(link);
                }
            if (links.empty()) continue;
            // A term that cannot be read (off the example) costs the copy's
            // mean term where it is, so that the sums of two translations
            // compare. Where it is, its cost is then the terms read plus
            // the penalty for each of the others (a sum in any order).
            int64_t penalty = 0, best = 0;
            {
                int64_t sum = 0, terms = 0;
                for (const Link& link : links) {
                    uint32_t onto;
                    if (link.has_view) sum += distance(link.mine, link.view), ++terms;
                    if (moved(link.mine, link.dx * s, link.dy * s, onto)) sum += distance(onto, link.there), ++terms;
                }
                penalty = terms ? sum / terms : 0;
                best = sum + (2 * int64_t(links.size()) - terms) * penalty;
            }
            // The mismatch of the copy moved by (tx, ty): across each link,
            // the copy's content against what the neighbour's copy would put
            // there, and the neighbour's against what this copy would put
            // there (Kwatra et al. 2003's seam cost), given up at `bound`.
            const auto cost = [&](int tx, int ty, int64_t bound) {
                int64_t sum = 0;
                for (const Link& link : links) {
                    const uint32_t mine = pack_position(position_x(link.mine) + tx, position_y(link.mine) + ty);
                    uint32_t onto;
                    sum += link.has_view ? distance(mine, link.view) : penalty;
                    sum += moved(mine, link.dx * s, link.dy * s, onto) ? distance(onto, link.there) : penalty;
                    if (sum >= bound) break;
                }
                return sum;
            };
            // Translations that keep the copy inside the example, drawn from
            // the copy's own seeded stream; the first lowest cost wins, the
            // copy where it is on a tie.
            const int lo_x = -min_x, span_x = ew - (max_x - min_x);
            const int lo_y = -min_y, span_y = eh - (max_y - min_y);
            const uint64_t base = coherent::pixel_hash(seed, level, kRelocationPurpose, int(first % uint32_t(w)),
                                                       int(first / uint32_t(w)));
            for (int t = 0; t < candidates; ++t) {
                const uint64_t r = mix64(base + uint64_t(t));
                const int tx = lo_x + int((r & 0xFFFFFFFF) % uint64_t(span_x));
                const int ty = lo_y + int((r >> 32) % uint64_t(span_y));
                const int64_t tried = cost(tx, ty, best);
                if (tried < best) {
                    best = tried;
                    move[c] = {tx, ty};
                }
            }
        }
    });
    for (std::size_t c = 0; c < copies.size(); ++c) {
        if (move[c].first == 0 && move[c].second == 0) continue;
        for (uint32_t q = start[copies[c]]; q < start[copies[c] + 1]; ++q) {
            uint32_t& p = pos[order[q]];
            p = pack_position(position_x(p) + move[c].first, position_y(p) + move[c].second);
        }
    }
}

}  // namespace vqtex
