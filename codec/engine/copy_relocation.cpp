// copy_relocation.cpp - moving whole copies to where they fit the copies
// around them (see copy_relocation.hpp; docs/SYNTHESIS.md "Session 11").
#include "engine/copy_relocation.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>
#include <vector>

#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_common.hpp"

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
    // Vectors are clamped to +-kAppearanceClamp, so a distance fits 32 bits
    // (8 squares of at most 4094^2).
    static_assert(int64_t(kAppearanceDims) * (2 * kAppearanceClamp) * (2 * kAppearanceClamp) < (int64_t(1) << 31),
                  "an appearance distance must fit int32_t");
    const auto distance = [&](uint32_t a, uint32_t b) {
        const int16_t* u = features + (std::size_t(position_y(a)) * std::size_t(ew) + position_x(a)) * kAppearanceDims;
        const int16_t* v = features + (std::size_t(position_y(b)) * std::size_t(ew) + position_x(b)) * kAppearanceDims;
        int32_t d = 0;
        for (int i = 0; i < kAppearanceDims; ++i) {
            const int32_t t = int32_t(u[i]) - int32_t(v[i]);
            d += t * t;
        }
        return int64_t(d);
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

    if (getenv("TMP_JACOBI")) {
        // Every copy scored against the map as it is, in parallel; then all moved.
        std::vector<uint32_t> start(n + 1, 0), order(n);
        for (std::size_t i = 0; i < n; ++i) ++start[label[i] + 1];
        for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
        {
            std::vector<uint32_t> fill(start.begin(), start.end() - 1);
            for (std::size_t i = 0; i < n; ++i) order[fill[label[i]]++] = uint32_t(i);
        }
        std::vector<uint32_t> roots;
        for (std::size_t i = 0; i < n; ++i)
            if (label[i] == i) roots.push_back(uint32_t(i));
        std::vector<std::pair<int, int>> move(roots.size(), {0, 0});
        parallel_for(threads, roots.size(), 4, [&](std::size_t r0, std::size_t r1) {
            std::vector<Link> lk;
            for (std::size_t ri = r0; ri < r1; ++ri) {
                const uint32_t first = roots[ri];
                const uint32_t* px = order.data() + start[first];
                const std::size_t count = start[first + 1] - start[first];
                if (2 * count >= n) continue;
                int min_x = ew, min_y = eh, max_x = 0, max_y = 0;
                for (std::size_t q = 0; q < count; ++q) {
                    const uint32_t p = pos[px[q]];
                    min_x = std::min(min_x, position_x(p)); max_x = std::max(max_x, position_x(p));
                    min_y = std::min(min_y, position_y(p)); max_y = std::max(max_y, position_y(p));
                }
                lk.clear();
                for (std::size_t q = 0; q < count; ++q)
                    for (int k = 0; k < 4; ++k) {
                        const std::size_t j = neighbour(px[q], k);
                        if (label[j] == first) continue;
                        Link link{pos[px[q]], pos[j], 0, false, int8_t(kStepX[k]), int8_t(kStepY[k])};
                        link.has_view = moved(pos[j], -kStepX[k] * s, -kStepY[k] * s, link.view);
                        lk.push_back(link);
                    }
                if (lk.empty()) continue;
                int64_t penalty = 0;
                {
                    int64_t sum = 0, terms = 0;
                    for (const Link& link : lk) {
                        uint32_t onto;
                        if (link.has_view) sum += distance(link.mine, link.view), ++terms;
                        if (moved(link.mine, link.dx * s, link.dy * s, onto)) sum += distance(onto, link.there), ++terms;
                    }
                    penalty = terms ? sum / terms : 0;
                }
                const auto cost = [&](int tx, int ty, int64_t bound) {
                    int64_t c = 0;
                    for (const Link& link : lk) {
                        const uint32_t mine = pack_position(position_x(link.mine) + tx, position_y(link.mine) + ty);
                        uint32_t onto;
                        c += link.has_view ? distance(mine, link.view) : penalty;
                        c += moved(mine, link.dx * s, link.dy * s, onto) ? distance(onto, link.there) : penalty;
                        if (c >= bound) break;
                    }
                    return c;
                };
                int64_t best = cost(0, 0, INT64_MAX);
                const int lo_x = -min_x, span_x = ew - (max_x - min_x);
                const int lo_y = -min_y, span_y = eh - (max_y - min_y);
                const uint64_t base = coherent::pixel_hash(seed, level, kRelocationPurpose, int(first % uint32_t(w)),
                                                           int(first / uint32_t(w)));
                for (int t = 0; t < candidates; ++t) {
                    const uint64_t r = coherent::mix64(base + uint64_t(t));
                    const int tx = lo_x + int((r & 0xFFFFFFFF) % uint64_t(span_x));
                    const int ty = lo_y + int((r >> 32) % uint64_t(span_y));
                    const int64_t c = cost(tx, ty, best);
                    if (c < best) { best = c; move[ri] = {tx, ty}; }
                }
            }
        });
        for (std::size_t ri = 0; ri < roots.size(); ++ri) {
            if (move[ri].first == 0 && move[ri].second == 0) continue;
            const uint32_t first = roots[ri];
            for (uint32_t q = start[first]; q < start[first + 1]; ++q) {
                uint32_t& p = pos[order[q]];
                p = pack_position(position_x(p) + move[ri].first, position_y(p) + move[ri].second);
            }
        }
        return;
    }
    // Copies one by one, by their first pixel; each sees the ones before it
    // where they were moved. A copy done is labelled kDone.
    constexpr uint32_t kDone = UINT32_MAX;
    std::vector<uint32_t> pixels, stack;
    std::vector<Link> links;
    for (std::size_t first = 0; first < n; ++first) {
        if (label[first] != first) continue;
        // Its pixels, in raster order.
        pixels.clear();
        stack.assign(1, uint32_t(first));
        label[first] = kDone - 1;  // marks pixels already gathered
        while (!stack.empty()) {
            const uint32_t i = stack.back();
            stack.pop_back();
            pixels.push_back(i);
            for (int k = 0; k < 4; ++k) {
                const std::size_t j = neighbour(i, k);
                if (label[j] == first) {
                    label[j] = kDone - 1;
                    stack.push_back(uint32_t(j));
                }
            }
        }
        std::sort(pixels.begin(), pixels.end());
        const auto finish = [&] {
            for (uint32_t i : pixels) label[i] = kDone;
        };
        // A copy covering half the level or more stays: the others are
        // moved to fit it.
        if (2 * pixels.size() >= n) {
            finish();
            continue;
        }
        int min_x = ew, min_y = eh, max_x = 0, max_y = 0;
        for (uint32_t i : pixels) {
            min_x = std::min(min_x, position_x(pos[i]));
            max_x = std::max(max_x, position_x(pos[i]));
            min_y = std::min(min_y, position_y(pos[i]));
            max_y = std::max(max_y, position_y(pos[i]));
        }
        links.clear();
        for (uint32_t i : pixels)
            for (int k = 0; k < 4; ++k) {
                const std::size_t j = neighbour(i, k);
                if (label[j] == kDone - 1) continue;  // the copy's own
                Link link{pos[i], pos[j], 0, false, int8_t(kStepX[k]), int8_t(kStepY[k])};
                link.has_view = moved(pos[j], -kStepX[k] * s, -kStepY[k] * s, link.view);
                links.push_back(link);
            }
        finish();
        static const std::size_t min_px = getenv("TMP_MINPX") ? std::size_t(atoi(getenv("TMP_MINPX"))) : 0;
        if (links.empty() || pixels.size() < min_px) continue;
        // A term that cannot be read (off the example) costs the copy's mean
        // term where it is, so that the sums of two translations compare.
        int64_t penalty = 0;
        {
            int64_t sum = 0, terms = 0;
            for (const Link& link : links) {
                uint32_t onto;
                if (link.has_view) sum += distance(link.mine, link.view), ++terms;
                if (moved(link.mine, link.dx * s, link.dy * s, onto)) sum += distance(onto, link.there), ++terms;
            }
            penalty = terms ? sum / terms : 0;
        }
        // The mismatch of the copy moved by (tx, ty) over every `stride`-th
        // link, given up at `bound`.
        const auto cost = [&](int tx, int ty, int64_t bound, std::size_t stride = 1) {
            int64_t c = 0;
            for (std::size_t li = 0; li < links.size(); li += stride) {
                const Link& link = links[li];
                const uint32_t mine = pack_position(position_x(link.mine) + tx, position_y(link.mine) + ty);
                uint32_t onto;
                c += link.has_view ? distance(mine, link.view) : penalty;
                c += moved(mine, link.dx * s, link.dy * s, onto) ? distance(onto, link.there) : penalty;
                if (c >= bound) break;
            }
            return c;
        };
        int64_t best = cost(0, 0, INT64_MAX);
        int best_x = 0, best_y = 0;
        const int lo_x = -min_x, span_x = ew - (max_x - min_x);
        const int lo_y = -min_y, span_y = eh - (max_y - min_y);
        const uint64_t base = coherent::pixel_hash(seed, level, kRelocationPurpose, int(first % std::size_t(w)),
                                                   int(first / std::size_t(w)));
        static const int per_link = getenv("TMP_PERLINK") ? atoi(getenv("TMP_PERLINK")) : 0;
        const int tried = per_link > 0 ? std::clamp(int(links.size()) * per_link / 4, 8, candidates) : candidates;
        static const bool from_neighbours = getenv("TMP_NEIGHBOURS") != nullptr;
        if (from_neighbours) {
            // The translations that make the copy continue a neighbouring copy across one of its links.
            std::vector<std::pair<int, int>> tried_moves;
            for (const Link& link : links) {
                if (!link.has_view) continue;
                const int tx = position_x(link.view) - position_x(link.mine), ty = position_y(link.view) - position_y(link.mine);
                if (tx == 0 && ty == 0) continue;
                if (tx < lo_x || tx >= lo_x + span_x || ty < lo_y || ty >= lo_y + span_y) continue;
                if (std::find(tried_moves.begin(), tried_moves.end(), std::make_pair(tx, ty)) != tried_moves.end()) continue;
                tried_moves.push_back({tx, ty});
                const int64_t c = cost(tx, ty, best);
                if (c < best) {
                    best = c;
                    best_x = tx;
                    best_y = ty;
                }
            }
        }
        static const std::size_t screen = getenv("TMP_SCREEN") ? std::size_t(atoi(getenv("TMP_SCREEN"))) : 0;
        static const int keep = getenv("TMP_KEEP") ? atoi(getenv("TMP_KEEP")) : 4;
        if (screen > 0 && links.size() > screen) {
            const std::size_t stride = (links.size() + screen - 1) / screen;
            std::vector<std::pair<int64_t, int>> screened;
            for (int t = 0; t < tried; ++t) {
                const uint64_t r = coherent::mix64(base + uint64_t(t));
                const int tx = lo_x + int((r & 0xFFFFFFFF) % uint64_t(span_x));
                const int ty = lo_y + int((r >> 32) % uint64_t(span_y));
                screened.push_back({cost(tx, ty, INT64_MAX, stride), t});
            }
            std::sort(screened.begin(), screened.end());
            for (int m = 0; m < keep && m < int(screened.size()); ++m) {
                const uint64_t r = coherent::mix64(base + uint64_t(screened[std::size_t(m)].second));
                const int tx = lo_x + int((r & 0xFFFFFFFF) % uint64_t(span_x));
                const int ty = lo_y + int((r >> 32) % uint64_t(span_y));
                const int64_t c = cost(tx, ty, best);
                if (c < best) {
                    best = c;
                    best_x = tx;
                    best_y = ty;
                }
            }
        } else {
            // The positions in chunks, one per thread when the copy has
            // links enough to pay for it: each chunk keeps its first
            // lowest cost under the unmoved copy's, and the chunks are
            // merged in order, so the first lowest over all positions wins,
            // as one thread would find it.
            const int chunks = threads > 1 && links.size() * std::size_t(tried) >= 4096 ? threads : 1;
            std::vector<int64_t> chunk_best(std::size_t(chunks), best);
            std::vector<int> chunk_x(std::size_t(chunks), 0), chunk_y(std::size_t(chunks), 0);
            const int per = (tried + chunks - 1) / chunks;
            parallel_for(chunks, std::size_t(chunks), 1, [&](std::size_t c0, std::size_t c1) {
                for (std::size_t ci = c0; ci < c1; ++ci)
                    for (int t = int(ci) * per; t < std::min(tried, int(ci + 1) * per); ++t) {
                        const uint64_t r = coherent::mix64(base + uint64_t(t));
                        const int tx = lo_x + int((r & 0xFFFFFFFF) % uint64_t(span_x));
                        const int ty = lo_y + int((r >> 32) % uint64_t(span_y));
                        const int64_t c = cost(tx, ty, chunk_best[ci]);
                        if (c < chunk_best[ci]) {
                            chunk_best[ci] = c;
                            chunk_x[ci] = tx;
                            chunk_y[ci] = ty;
                        }
                    }
            });
            for (int ci = 0; ci < chunks; ++ci)
                if (chunk_best[std::size_t(ci)] < best) {
                    best = chunk_best[std::size_t(ci)];
                    best_x = chunk_x[std::size_t(ci)];
                    best_y = chunk_y[std::size_t(ci)];
                }
        }
        if (best_x != 0 || best_y != 0)
            for (uint32_t i : pixels)
                pos[i] = pack_position(position_x(pos[i]) + best_x, position_y(pos[i]) + best_y);
    }
}

}  // namespace vqtex
