// coherent_synthesis.cpp - coordinate synthesis with k-coherence candidates
// in appearance space (Lefebvre & Hoppe 2005 sections 3-4, 2006 section 4;
// Tong et al. 2002; Ashikhmin 2001). See coherent_synthesis.hpp.
#include "engine/coherent_synthesis.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/coherent_candidates.hpp"
#include "engine/pyramid.hpp"

namespace vqtex {
namespace {

// Neighbourhood of a correction step: the 5x5 window of appearance
// vectors (each already summarises a 5x5 window of its level).
constexpr int kRadius = 2;
constexpr int kSide = 2 * kRadius + 1;
static_assert(kAppearanceDims == dsp::kWindowTapValues, "windows are compared by dsp::Kernels::window_ssd");
constexpr int kTaps = kSide * kSide;
static_assert(kTaps < 32, "a window's taps are bits of one uint32_t");
constexpr int kMaxCandidates = kTaps * 16;

uint64_t mix64(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// A per-pixel hash of the seed, the level and a purpose: the same pixel of
// the same level gets the same numbers whatever else is computed.
uint64_t pixel_hash(uint64_t seed, int level, int purpose, int x, int y) {
    return mix64(seed ^ mix64((uint64_t(uint32_t(level)) << 40) ^ (uint64_t(uint32_t(purpose)) << 56) ^
                              (uint64_t(uint32_t(y)) << 20) ^ uint64_t(uint32_t(x))));
}

// Position (x, y) of the example, folded inside if it is not.
uint32_t folded(const AppearanceSpace& space, int x, int y) {
    return pack_position(space.fold_x(x), space.fold_y(y));
}

struct LevelView {
    const AppearanceSpace& space;
    const CoherenceSets& sets;
    int level;       // for the coherence sets
    int spacing;
    const int16_t* features;  // kAppearanceDims per example pixel
    int k;           // coherence candidates per neighbour
    const dsp::Kernels& kernels;

    const int16_t* feature(int x, int y) const {
        return features + (std::size_t(y) * space.width + x) * kAppearanceDims;
    }
    const int16_t* feature(uint32_t p) const { return feature(position_x(p), position_y(p)); }

    // Distance between the query (kTaps vectors) and the example's window at
    // (x, y), stopping once it exceeds `bound` (Kernels::window_ssd).
    uint32_t distance(const int16_t* query, int x, int y, uint32_t bound) const {
        const int w = space.width, h = space.height;
        const std::ptrdiff_t tap = std::ptrdiff_t(spacing) * kAppearanceDims;
        if (x - kRadius * spacing >= 0 && x + kRadius * spacing < w && y - kRadius * spacing >= 0 &&
            y + kRadius * spacing < h)
            return kernels.window_ssd(query, feature(x - kRadius * spacing, y - kRadius * spacing), tap,
                                      tap * w, kSide, bound);
        // Windows across the example's edge read it folded: their taps are
        // gathered side by side first, for the same kernel and the same sums.
        alignas(16) int16_t window[kTaps * kAppearanceDims];
        int xs[kSide], ys[kSide];
        for (int i = 0; i < kSide; ++i) {
            const int sx = x + (i - kRadius) * spacing, sy = y + (i - kRadius) * spacing;
            xs[i] = sx >= 0 && sx < w ? sx : space.fold_x(sx);
            ys[i] = sy >= 0 && sy < h ? sy : space.fold_y(sy);
        }
        for (int r = 0, t = 0; r < kSide; ++r)
            for (int c = 0; c < kSide; ++c, ++t)
                std::memcpy(window + t * kAppearanceDims, feature(xs[c], ys[r]), sizeof(int16_t) * kAppearanceDims);
        return kernels.window_ssd(query, window, kAppearanceDims, std::ptrdiff_t(kSide) * kAppearanceDims, kSide,
                                  bound);
    }
};

// One correction of pixel (x, y) of `cur` (w x h, a torus; xs and ys are
// the wrapped columns and rows of its window): the best of its neighbours'
// coherent candidates.
uint32_t correct_pixel(const LevelView& v, const uint32_t* cur, int w, const int* xs, const int* ys, int bias,
                       int link_bias) {
    uint32_t sources[kTaps];
    for (int r = 0, t = 0; r < kSide; ++r) {
        const uint32_t* row = cur + std::size_t(ys[r]) * w;
        for (int c = 0; c < kSide; ++c, ++t) sources[t] = row[xs[c]];
    }
    const uint32_t own_position = sources[kTaps / 2];
    // Bit t set: neighbour t's source is not the pixel's own shifted by the
    // neighbour's offset, so it may propose another position. Inside a
    // coherent copy no bit is set and there is nothing to compare: checked
    // first, branch-free, because that holds for most pixels.
    uint32_t proposing = (1u << kTaps) - 1;
    {
        const int ox = position_x(own_position), oy = position_y(own_position);
        const int reach = kRadius * v.spacing;
        if (ox >= reach && oy >= reach && ox + reach < v.space.width && oy + reach < v.space.height) {
            proposing = 0;
            for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
                for (int dx = -kRadius; dx <= kRadius; ++dx, ++t)
                    proposing |= uint32_t(sources[t] != pack_position(ox + dx * v.spacing, oy + dy * v.spacing)) << t;
            if (proposing == 0 && v.k == 1) return own_position;
        }
    }
    // No two adjacent pixels of the example share a position, so a
    // candidate that one of the four nearest neighbours holds would repeat a
    // pixel: it is not offered (k = 1). Without this rule, 1.4% of the
    // adjacent pixel pairs of a gravel output were repeats, against 0.07%
    // in its example.
    const auto held_next_door = [&](uint32_t c) {
        return c == sources[kTaps / 2 - kSide] || c == sources[kTaps / 2 - 1] || c == sources[kTaps / 2 + 1] ||
               c == sources[kTaps / 2 + kSide];
    };
    CandidateList<kMaxCandidates> candidates;
    const int ex_w = v.space.width, ex_h = v.space.height;
    const int k = std::min(v.k, kMaxCandidates / kTaps);
    // With k = 1 only the proposing neighbours are visited: a neighbour that
    // continues the pixel's own copy proposes the pixel's own position,
    // which is evaluated first anyway.
    for (uint32_t taps = k == 1 ? proposing : (1u << kTaps) - 1; taps != 0; taps &= taps - 1) {
        const int t = __builtin_ctz(taps);
        const ShiftedSource u = shifted_source(position_x(sources[t]), position_y(sources[t]), t % kSide - kRadius,
                                               t / kSide - kRadius, v.spacing);
        int ux = u.x, uy = u.y;
        if (v.space.wraps) {
            ux = Image::wrap(ux, ex_w);
            uy = Image::wrap(uy, ex_h);
        } else if (ux < 0 || uy < 0 || ux >= ex_w || uy >= ex_h) {
            continue;  // the neighbour's source continues past the example's edge
        }
        if (k == 1) {
            const uint32_t c = pack_position(ux, uy);
            if (c != own_position && !held_next_door(c)) candidates.add(c, true);
            continue;
        }
        const uint32_t* set = v.sets.of(v.level, uint32_t(uy) * uint32_t(ex_w) + uint32_t(ux));
        for (int i = 0; i < k; ++i)
            candidates.add(pack_position(int(set[i] % uint32_t(ex_w)), int(set[i] / uint32_t(ex_w))), i == 0);
    }
    const int count = candidates.size();
    // Inside a coherent copy every neighbour proposes the pixel's own
    // position: nothing to compare.
    if (count == 0) return own_position;
    alignas(32) int16_t query[kTaps * kAppearanceDims];
    for (int t = 0; t < kTaps; ++t)
        std::memcpy(query + t * kAppearanceDims, v.feature(sources[t]), sizeof(int16_t) * kAppearanceDims);
    // The pixel's own position competes too, first and unbiased (its source
    // may be off the example's edge for every neighbour); unless it repeats
    // a neighbour's, when any candidate takes its place.
    // Each of the four nearest neighbours that does not continue a
    // candidate's copy surcharges its distance by `link_bias`: a position
    // that sits inside one copy with its neighbours beats one that a
    // single neighbour proposes. This is what breaks up combs, patches
    // whose alternate rows or columns hold two different copies, where every
    // pixel sees its own copy on two sides and the other on two.
    const auto surcharge = [&](uint32_t c) {
        const int cx = position_x(c), cy = position_y(c), s = v.spacing;
        const int links = int(sources[kTaps / 2 - kSide] == pack_position(cx, cy - s)) +
                          int(sources[kTaps / 2 + kSide] == pack_position(cx, cy + s)) +
                          int(sources[kTaps / 2 - 1] == pack_position(cx - s, cy)) +
                          int(sources[kTaps / 2 + 1] == pack_position(cx + s, cy));
        return uint64_t(256) + uint64_t(link_bias) * uint64_t(4 - links);
    };
    const auto scaled = [](uint64_t d, uint64_t factor) { return uint32_t(std::min<uint64_t>(UINT32_MAX, d * factor / 256)); };
    uint32_t best = own_position;
    uint32_t best_d = held_next_door(own_position)
                          ? UINT32_MAX
                          : scaled(v.distance(query, position_x(best), position_y(best), UINT32_MAX), surcharge(best));
    for (int i = 0; i < count; ++i) {
        // An alternative that continues no neighbour's copy must beat the
        // best by the bias besides: d (1 + bias/256) < best. One factor, in
        // 1/65536, so that the bound below is exact: a window given up
        // once past it could not have won.
        const uint64_t factor = surcharge(candidates[i]) * (candidates.continues(i) ? 256 : uint64_t(256 + bias));
        const uint32_t bound = uint32_t(std::min<uint64_t>(UINT32_MAX, uint64_t(best_d) * 65536 / factor));
        const uint32_t d = uint32_t(std::min<uint64_t>(
            UINT32_MAX, uint64_t(v.distance(query, position_x(candidates[i]), position_y(candidates[i]), bound)) *
                            factor / 65536));
        if (d < best_d) {
            best_d = d;
            best = candidates[i];
        }
    }
    return best;
}

// A child's coordinate from its parent's. A parent whose second child
// would fall past the example's edge has its block of children moved inside
// whole, so the block stays a coherent copy; folding the child back (a
// mirror) repeated the same rows over several levels and drew streaks.
int child_coordinate(int size, bool wraps, int parent, int offset, int spacing) {
    if (wraps) return Image::wrap(parent + offset * spacing, size);
    const int base = parent + spacing < size ? parent : std::max(0, size - 1 - spacing);
    return std::min(base + offset * spacing, size - 1);
}

// Which pixels a pass must evaluate again. A pixel's correction depends
// only on the positions in its window, so a pixel none of whose window has
// moved since its last evaluation would choose what it holds already:
// skipping it gives the same bytes. Over the passes of one level (same
// features) this skips most of the second pass.
struct Revisit {
    std::vector<uint8_t> due;    // evaluate at its next turn
    std::vector<uint8_t> moved;  // changed at its last evaluation
    explicit Revisit(std::size_t pixels) : due(pixels, 1), moved(pixels, 0) {}
};

// One correction pass over the whole level, in kStride x kStride
// interleaved subsets (a pixel and the others of its subset are kStride
// apart); each subset reads only the positions as they were before it. A
// subset's choices go to a buffer of its own size first, since its rows
// read one another's windows, and are put in place once it is done.
// Lefebvre & Hoppe's 2: pixels 3 apart broke up combs too, but less than
// the link bias does, and with 4 apart more combs were left (SYNTHESIS.md).
constexpr int kStride = 2;

// The subsets in diagonal order, so that consecutive ones are not
// neighbours along a row or a column.
constexpr std::array<std::array<int, 2>, kStride * kStride> subset_order() {
    std::array<std::array<int, 2>, kStride * kStride> order{};
    for (int a = 0, i = 0; a < kStride; ++a)
        for (int b = 0; b < kStride; ++b, ++i) order[std::size_t(i)] = {(a + b) % kStride, b};
    return order;
}

void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options,
                     Revisit* revisit = nullptr) {
    constexpr auto kOrder = subset_order();
    const int w = map.width, h = map.height;
    std::vector<uint32_t> chosen(std::size_t((w + kStride - 1) / kStride) * std::size_t((h + kStride - 1) / kStride));
    for (const auto& subset : kOrder) {
        // Plain ints: clang 14 cannot capture structured bindings in a lambda.
        const int sx = subset[0], sy = subset[1];
        const int rows = (h - sy + kStride - 1) / kStride, cols = (w - sx + kStride - 1) / kStride;
        if (rows <= 0 || cols <= 0) continue;
        const uint32_t* positions = map.positions.data();
        parallel_for(options.threads, std::size_t(rows), 4, [&](std::size_t r0, std::size_t r1) {
            int xs[kSide], ys[kSide];
            for (std::size_t r = r0; r < r1; ++r) {
                const int y = sy + kStride * int(r);
                uint32_t* out = chosen.data() + r * std::size_t(cols);
                for (int i = 0; i < kSide; ++i) ys[i] = Image::wrap(y + i - kRadius, h);
                for (int i = 0; i < kSide; ++i) xs[i] = Image::wrap(sx + i - kRadius, w);
                for (int x = sx, i = 0; x < w; x += kStride, ++i) {
                    const std::size_t at = std::size_t(y) * w + x;
                    if (!revisit) {
                        out[i] = correct_pixel(view, positions, w, xs, ys, options.coherence_bias, options.link_bias);
                    } else if (revisit->due[at]) {
                        out[i] = correct_pixel(view, positions, w, xs, ys, options.coherence_bias, options.link_bias);
                        revisit->due[at] = 0;
                        revisit->moved[at] = out[i] != positions[at];
                    } else {
                        out[i] = positions[at];
                    }
                    // Slide the window kStride columns: wrap by comparison
                    // except on outputs narrower than the window.
                    for (int j = 0; j < kSide; ++j) {
                        int c = xs[j] + kStride;
                        if (c >= w) c = w >= kSide ? c - w : Image::wrap(x + kStride + j - kRadius, w);
                        xs[j] = c;
                    }
                }
            }
        });
        parallel_for(options.threads, std::size_t(rows), 16, [&](std::size_t r0, std::size_t r1) {
            for (std::size_t r = r0; r < r1; ++r) {
                uint32_t* row = map.positions.data() + (sy + kStride * r) * std::size_t(w);
                const uint32_t* in = chosen.data() + r * std::size_t(cols);
                for (int i = 0; i < cols; ++i) row[sx + kStride * i] = in[i];
            }
        });
        if (revisit) {
            // Every pixel whose window holds a moved one is due again; marked
            // after the subset, on one thread, so no flag is written twice at once.
            for (int y = sy; y < h; y += kStride)
                for (int x = sx; x < w; x += kStride) {
                    uint8_t& moved = revisit->moved[std::size_t(y) * w + x];
                    if (!moved) continue;
                    moved = 0;
                    for (int dy = -kRadius; dy <= kRadius; ++dy) {
                        uint8_t* row = revisit->due.data() + std::size_t(Image::wrap(y + dy, h)) * w;
                        for (int dx = -kRadius; dx <= kRadius; ++dx) row[Image::wrap(x + dx, w)] = 1;
                    }
                }
        }
    }
}

}  // namespace

void correct_positions(const AppearanceSpace& space, const CoherenceSets& sets, int level, PositionMap& map,
                       const CoherentOptions& options) {
    const int spacing = space.levels[std::size_t(level)].spacing;
    const LevelView view{space, sets, level, spacing, space.levels[std::size_t(level)].features.data(), sets.k,
                         dsp::kernels()};
    correction_pass(view, map, options);
}

PositionMap upsample_positions(const AppearanceSpace& space, const PositionMap& parent, int width, int height,
                               int spacing, int threads) {
    PositionMap out{width, height, std::vector<uint32_t>(std::size_t(width) * height)};
    parallel_for(threads, std::size_t(height), 16, [&](std::size_t y0, std::size_t y1) {
        for (int y = int(y0); y < int(y1); ++y)
            for (int x = 0; x < width; ++x) {
                const uint32_t p = parent.positions[std::size_t(y >> 1) * parent.width + (x >> 1)];
                out.positions[std::size_t(y) * width + x] =
                    pack_position(child_coordinate(space.width, space.wraps, position_x(p), x & 1, spacing),
                                  child_coordinate(space.height, space.wraps, position_y(p), y & 1, spacing));
            }
    });
    return out;
}

PositionMap synthesize_positions(const AppearanceSpace& space, const CoherenceSets& sets,
                                 const CoherentOptions& options, std::vector<PositionMap>* levels) {
    const int top = int(space.levels.size()) - 1;
    uint64_t total = 0, done = 0;
    for (int l = top; l >= 0; --l) {
        const uint64_t area = uint64_t(pyramid_level_size(options.width, l)) * pyramid_level_size(options.height, l);
        total += area * uint64_t(l == top ? options.coarse_passes : options.passes);
    }
    PositionMap map;
    if (levels) levels->assign(space.levels.size(), PositionMap{});
    for (int l = top; l >= 0; --l) {
        const int w = pyramid_level_size(options.width, l), h = pyramid_level_size(options.height, l);
        const int spacing = space.levels[std::size_t(l)].spacing;
        if (l == top) {
            // The coarsest level starts anywhere: positions drawn at random.
            map = PositionMap{w, h, std::vector<uint32_t>(std::size_t(w) * h)};
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const uint64_t r = pixel_hash(options.seed, l, 0, x, y);
                    map.positions[std::size_t(y) * w + x] =
                        pack_position(int((r & 0xFFFFFFFF) % uint64_t(space.width)), int((r >> 32) % uint64_t(space.height)));
                }
        } else {
            map = upsample_positions(space, map, w, h, spacing, options.threads);
            // Jitter of up to jitter/256 of the spacing in x and y.
            const int64_t reach = int64_t(spacing) * options.jitter;
            if (reach > 0)
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const uint64_t r = pixel_hash(options.seed, l, 1, x, y);
                        const int64_t jx = ((int64_t(r & 0xFFFF) - 32768) * reach) / (32768 * 256);
                        const int64_t jy = ((int64_t((r >> 16) & 0xFFFF) - 32768) * reach) / (32768 * 256);
                        uint32_t& p = map.positions[std::size_t(y) * w + x];
                        p = folded(space, position_x(p) + int(jx), position_y(p) + int(jy));
                    }
        }
        const LevelView view{space, sets, l, spacing, space.levels[std::size_t(l)].features.data(), sets.k, dsp::kernels()};
        const int passes = l == top ? options.coarse_passes : options.passes;
        Revisit revisit(map.positions.size());
        for (int pass = 0; pass < passes; ++pass) {
            correction_pass(view, map, options, &revisit);
            done += uint64_t(w) * h;
            if (options.progress && !options.progress(done, total))
                fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        if (l == 0 && options.polish_passes > 0) {
            // Seams between coherent copies are placed by colours at last:
            // the coherence of the output's own pixels is what a viewer sees.
            const LevelView polish{space, sets, 0, 1, space.pixels.data(), 1, dsp::kernels()};
            Revisit revisit_colours(map.positions.size());
            for (int pass = 0; pass < options.polish_passes; ++pass) correction_pass(polish, map, options, &revisit_colours);
        }
        if (levels) (*levels)[std::size_t(l)] = map;
    }
    // Where to cut the torus open is free: the output's origin is put on the
    // column and the row across which the pixels change least. Left at the
    // coarsest level's grid, the edges lay where coherent copies tend to
    // meet, and on 6 of 23 corpus textures the wrap was a visible line.
    const Image seen = read_positions(space.levels[0].colours, map, options.threads);
    const int channels = seen.channels;
    auto step = [&](const uint8_t* a, const uint8_t* b) {
        int d = 0;
        for (int c = 0; c < channels; ++c) d += std::abs(int(a[c]) - int(b[c]));
        return d;
    };
    int ox = 0, oy = 0;
    std::vector<int64_t> across_column(std::size_t(map.width), 0);
    int64_t best_y = INT64_MAX;
    for (int y = 0; y < map.height; ++y) {
        const uint8_t* row = seen.at(0, y);
        const uint8_t* above = seen.at(0, (y + map.height - 1) % map.height);
        int64_t sum = 0;
        for (int x = 0; x < map.width; ++x) {
            const uint8_t* left = seen.at((x + map.width - 1) % map.width, y);
            across_column[std::size_t(x)] += step(left, row + std::size_t(x) * channels);
            sum += step(above + std::size_t(x) * channels, row + std::size_t(x) * channels);
        }
        if (sum < best_y) best_y = sum, oy = y;
    }
    int64_t best_x = INT64_MAX;
    for (int x = 0; x < map.width; ++x)
        if (across_column[std::size_t(x)] < best_x) best_x = across_column[std::size_t(x)], ox = x;
    if (options.roll && (ox || oy)) {
        std::vector<uint32_t> rolled(map.positions.size());
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                rolled[std::size_t(y) * map.width + x] =
                    map.positions[std::size_t(Image::wrap(y + oy, map.height)) * map.width + Image::wrap(x + ox, map.width)];
        map.positions.swap(rolled);
    }
    return map;
}

Image read_positions(const Image& example, const PositionMap& map, int threads) {
    Image out(map.width, map.height, example.channels);
    parallel_for(threads, std::size_t(map.height), 16, [&](std::size_t y0, std::size_t y1) {
        for (int y = int(y0); y < int(y1); ++y)
            for (int x = 0; x < map.width; ++x) {
                const uint32_t p = map.positions[std::size_t(y) * map.width + x];
                copy_pixel(out.at(x, y), example.at(position_x(p), position_y(p)), example.channels);
            }
    });
    return out;
}

}  // namespace vqtex
