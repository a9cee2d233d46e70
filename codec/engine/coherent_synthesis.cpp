// coherent_synthesis.cpp - coordinate synthesis with k-coherence candidates
// in appearance space (Lefebvre & Hoppe 2005 sections 3-4, 2006 section 4;
// Tong et al. 2002; Ashikhmin 2001). See coherent_synthesis.hpp.
#include "engine/coherent_synthesis.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/pyramid.hpp"

namespace vqtex {
namespace {

// Neighbourhood of a correction step: the 5x5 window of appearance
// vectors (each already summarises a 5x5 window of its level).
constexpr int kRadius = 2;
constexpr int kSide = 2 * kRadius + 1;
static_assert(kAppearanceDims == dsp::kWindowTapValues, "windows are compared by dsp::Kernels::window_ssd");
constexpr int kTaps = kSide * kSide;
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
uint32_t correct_pixel(const LevelView& v, const uint32_t* cur, int w, const int* xs, const int* ys, int bias) {
    uint32_t sources[kTaps];
    for (int r = 0, t = 0; r < kSide; ++r) {
        const uint32_t* row = cur + std::size_t(ys[r]) * w;
        for (int c = 0; c < kSide; ++c, ++t) sources[t] = row[xs[c]];
    }
    const uint32_t own_position = sources[kTaps / 2];
    {
        // Inside a coherent copy every neighbour's source is the pixel's own
        // shifted by the neighbour's offset: then every candidate is the
        // pixel's own position, and there is nothing to compare. Checked
        // first, branch-free, because it holds for most pixels.
        const int ox = position_x(own_position), oy = position_y(own_position);
        const int reach = kRadius * v.spacing;
        if (ox >= reach && oy >= reach && ox + reach < v.space.width && oy + reach < v.space.height) {
            uint32_t differ = 0;
            for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
                for (int dx = -kRadius; dx <= kRadius; ++dx, ++t)
                    differ |= sources[t] ^ pack_position(ox + dx * v.spacing, oy + dy * v.spacing);
            if (differ == 0 && v.k == 1) return own_position;
        }
    }
    uint32_t candidates[kMaxCandidates];
    bool continues[kMaxCandidates];
    int count = 0;
    const int ex_w = v.space.width, ex_h = v.space.height;
    const int k = std::min(v.k, kMaxCandidates / kTaps);
    for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
        for (int dx = -kRadius; dx <= kRadius; ++dx, ++t) {
            int ux = position_x(sources[t]) - dx * v.spacing, uy = position_y(sources[t]) - dy * v.spacing;
            if (v.space.wraps) {
                ux = Image::wrap(ux, ex_w);
                uy = Image::wrap(uy, ex_h);
            } else if (ux < 0 || uy < 0 || ux >= ex_w || uy >= ex_h) {
                continue;  // the neighbour's source continues past the example's edge
            }
            if (k == 1) {
                // The pixel's own position is evaluated first anyway.
                const uint32_t c = pack_position(ux, uy);
                if (c == own_position) continue;
                int seen = -1;
                for (int j = 0; j < count && seen < 0; ++j)
                    if (candidates[j] == c) seen = j;
                if (seen < 0) {
                    continues[count] = true;
                    candidates[count++] = c;
                }
                continue;
            }
            const uint32_t* set = v.sets.of(v.level, uint32_t(uy) * uint32_t(ex_w) + uint32_t(ux));
            for (int i = 0; i < k; ++i) {
                const uint32_t c = pack_position(int(set[i] % uint32_t(ex_w)), int(set[i] / uint32_t(ex_w)));
                int seen = -1;
                for (int j = 0; j < count && seen < 0; ++j)
                    if (candidates[j] == c) seen = j;
                if (seen >= 0) {
                    continues[seen] = continues[seen] || i == 0;
                } else {
                    continues[count] = i == 0;
                    candidates[count++] = c;
                }
            }
        }
    // Inside a coherent copy every neighbour proposes the pixel's own
    // position: nothing to compare.
    if (count == 0) return own_position;
    alignas(32) int16_t query[kTaps * kAppearanceDims];
    for (int t = 0; t < kTaps; ++t)
        std::memcpy(query + t * kAppearanceDims, v.feature(sources[t]), sizeof(int16_t) * kAppearanceDims);
    // The pixel's own position competes too, first and unbiased (its source
    // may be off the example's edge for every neighbour).
    uint32_t best = own_position;
    uint32_t best_d = v.distance(query, position_x(best), position_y(best), UINT32_MAX);
    for (int i = 0; i < count; ++i) {
        // An alternative must beat the best by the bias: d (1 + bias/256) < best.
        const uint32_t bound = continues[i] ? best_d : uint32_t((uint64_t(best_d) * 256) / uint64_t(256 + bias));
        uint32_t d = v.distance(query, position_x(candidates[i]), position_y(candidates[i]), bound);
        if (!continues[i]) d = uint32_t(std::min<uint64_t>(UINT32_MAX, uint64_t(d) + (uint64_t(d) * uint64_t(bias)) / 256));
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

// One correction pass over the whole level, in four interleaved subsets;
// each subset reads only the positions as they were before it.
void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options) {
    static constexpr int kOrder[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    const int w = map.width, h = map.height;
    std::vector<uint32_t> next;
    for (const auto& subset : kOrder) {
        // Plain ints: clang 14 cannot capture structured bindings in a lambda.
        const int sx = subset[0], sy = subset[1];
        next = map.positions;
        const int rows = (h - sy + 1) / 2;
        parallel_for(options.threads, std::size_t(std::max(rows, 0)), 4, [&](std::size_t r0, std::size_t r1) {
            int xs[kSide], ys[kSide];
            for (std::size_t r = r0; r < r1; ++r) {
                const int y = sy + 2 * int(r);
                for (int i = 0; i < kSide; ++i) ys[i] = Image::wrap(y + i - kRadius, h);
                for (int i = 0; i < kSide; ++i) xs[i] = Image::wrap(sx + i - kRadius, w);
                for (int x = sx; x < w; x += 2) {
                    next[std::size_t(y) * w + x] =
                        correct_pixel(view, map.positions.data(), w, xs, ys, options.coherence_bias);
                    // Slide the window two columns: wrap by comparison
                    // except on outputs narrower than the window.
                    for (int i = 0; i < kSide; ++i) {
                        int c = xs[i] + 2;
                        if (c >= w) c = w >= kSide ? c - w : Image::wrap(x + 2 + i - kRadius, w);
                        xs[i] = c;
                    }
                }
            }
        });
        map.positions.swap(next);
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
                               int spacing) {
    PositionMap out{width, height, std::vector<uint32_t>(std::size_t(width) * height)};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint32_t p = parent.positions[std::size_t(y >> 1) * parent.width + (x >> 1)];
            out.positions[std::size_t(y) * width + x] =
                pack_position(child_coordinate(space.width, space.wraps, position_x(p), x & 1, spacing),
                              child_coordinate(space.height, space.wraps, position_y(p), y & 1, spacing));
        }
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
            map = upsample_positions(space, map, w, h, spacing);
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
        for (int pass = 0; pass < passes; ++pass) {
            correction_pass(view, map, options);
            done += uint64_t(w) * h;
            if (options.progress && !options.progress(done, total))
                fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        if (l == 0 && options.polish_passes > 0) {
            // Seams between coherent copies are placed by colours at last:
            // the coherence of the output's own pixels is what a viewer sees.
            const LevelView polish{space, sets, 0, 1, space.pixels.data(), 1, dsp::kernels()};
            for (int pass = 0; pass < options.polish_passes; ++pass) correction_pass(polish, map, options);
        }
        if (levels) (*levels)[std::size_t(l)] = map;
    }
    // Where to cut the torus open is free: the output's origin is put on the
    // column and the row across which the pixels change least. Left at the
    // coarsest level's grid, the edges lay where coherent copies tend to
    // meet, and on 6 of 23 corpus textures the wrap was a visible line.
    const Image& colours = space.levels[0].colours;
    auto step = [&](int x0, int y0, int x1, int y1) {
        const uint8_t* a = colours.at(position_x(map.positions[std::size_t(y0) * map.width + x0]),
                                      position_y(map.positions[std::size_t(y0) * map.width + x0]));
        const uint8_t* b = colours.at(position_x(map.positions[std::size_t(y1) * map.width + x1]),
                                      position_y(map.positions[std::size_t(y1) * map.width + x1]));
        int d = 0;
        for (int c = 0; c < colours.channels; ++c) d += std::abs(int(a[c]) - int(b[c]));
        return d;
    };
    int ox = 0, oy = 0;
    int64_t best_x = INT64_MAX, best_y = INT64_MAX;
    for (int x = 0; x < map.width; ++x) {
        int64_t sum = 0;
        for (int y = 0; y < map.height; ++y) sum += step((x + map.width - 1) % map.width, y, x, y);
        if (sum < best_x) best_x = sum, ox = x;
    }
    for (int y = 0; y < map.height; ++y) {
        int64_t sum = 0;
        for (int x = 0; x < map.width; ++x) sum += step(x, (y + map.height - 1) % map.height, x, y);
        if (sum < best_y) best_y = sum, oy = y;
    }
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

int coherent_levels(int width, int height) {
    int levels = 1;
    while (levels < 8 && (4 << levels) <= std::min(width, height)) ++levels;
    return levels;
}

CoherentResult synthesize_coherent(const Image& example, int levels, bool example_tileable, int coherence,
                                   const CoherentOptions& options,
                                   const std::function<bool(uint64_t, uint64_t)>& analyse_progress) {
    using Clock = std::chrono::steady_clock;
    if (example.width > 65535 || example.height > 65535)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "example larger than 65535 pixels on a side");
    const auto t0 = Clock::now();
    if (analyse_progress && !analyse_progress(0, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const AppearanceSpace space = build_appearance_space(example, levels, example_tileable, options.threads);
    const CoherenceSets sets = build_coherence_sets(space, coherence, 2, options.threads);
    if (analyse_progress && !analyse_progress(1, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const auto t1 = Clock::now();
    CoherentResult r;
    r.image = read_positions(example, synthesize_positions(space, sets, options));
    for (const auto& l : space.levels) r.model_bytes += l.colours.byte_count() + l.features.size() * sizeof(int16_t);
    for (const auto& l : sets.levels) r.model_bytes += l.size() * sizeof(uint32_t);
    r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
    r.synthesise_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return r;
}

Image read_positions(const Image& example, const PositionMap& map) {
    Image out(map.width, map.height, example.channels);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            const uint32_t p = map.positions[std::size_t(y) * map.width + x];
            copy_pixel(out.at(x, y), example.at(position_x(p), position_y(p)), example.channels);
        }
    return out;
}

}  // namespace vqtex
