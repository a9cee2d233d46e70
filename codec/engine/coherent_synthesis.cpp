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
#include "engine/coherent_candidates.hpp"
#include "engine/coherent_common.hpp"
#include "engine/pyramid.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {
namespace {

using coherent::kRadius;
using coherent::kSide;
using coherent::kTaps;
using coherent::pixel_hash;
static_assert(kTaps < 32, "a window's taps are bits of one uint32_t");
constexpr int kMaxCandidates = kTaps * 16;

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
    // (x, y), stopping once it exceeds `bound`.
    uint32_t distance(const int16_t* query, int x, int y, uint32_t bound) const {
        return coherent::window_distance(kernels, space, features, spacing, query, x, y, bound);
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

// One correction pass over the whole level (coherent::interleaved_pass).
void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options,
                     coherent::Revisit* revisit = nullptr) {
    const int w = map.width;
    coherent::interleaved_pass(
        options.threads, map.width, map.height, map.positions,
        [&](int, int, const int* xs, const int* ys) {
            return correct_pixel(view, map.positions.data(), w, xs, ys, options.coherence_bias, options.link_bias);
        },
        revisit);
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
                    pack_position(coherent::child_coordinate(space.width, space.wraps, position_x(p), x & 1, spacing),
                                  coherent::child_coordinate(space.height, space.wraps, position_y(p), y & 1, spacing));
            }
    });
    return out;
}

PositionMap synthesize_positions(const AppearanceSpace& space, const CoherenceSets& sets,
                                 const CoherentOptions& options) {
    const int top = int(space.levels.size()) - 1;
    // The finest level runs one pass fewer: the colour polish follows it,
    // and with the link bias its second pass changed the corpus scores by
    // under 0.5% for a tenth of the synthesis time (SYNTHESIS.md).
    const auto passes_at = [&](int l) {
        return l == top ? options.coarse_passes : l == 0 ? std::max(1, options.passes - 1) : options.passes;
    };
    uint64_t total = 0, done = 0;
    for (int l = top; l >= 0; --l) {
        const uint64_t area = uint64_t(pyramid_level_size(options.width, l)) * pyramid_level_size(options.height, l);
        total += area * uint64_t(passes_at(l));
    }
    PositionMap map;
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
        const int passes = passes_at(l);
        coherent::Revisit revisit(map.positions.size());
        for (int pass = 0; pass < passes; ++pass) {
            correction_pass(view, map, options, &revisit);
            done += uint64_t(w) * h;
            if (options.progress && !options.progress(done, total))
                fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        if (l == 0 && options.polish_passes > 0) {
            // Seams between coherent copies are placed by colours at last:
            // the coherence of the output's own pixels is what a viewer sees.
            // Every pixel is due again (other features); the flags of the
            // level's passes are reused rather than a second set allocated
            // beside them (a byte per output pixel).
            const LevelView polish{space, sets, 0, 1, space.pixels.data(), 1, dsp::kernels()};
            std::fill(revisit.due.begin(), revisit.due.end(), uint8_t(1));
            for (int pass = 0; pass < options.polish_passes; ++pass) correction_pass(polish, map, options, &revisit);
        }
    }
    return map;
}

int coherent_levels(int width, int height) {
    int levels = 1;
    while (levels < VQTEX_MAX_LEVELS && (4 << levels) <= std::min(width, height)) ++levels;
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
    r.image = read_positions(example, synthesize_positions(space, sets, options), options.roll, options.threads);
    for (const auto& l : space.levels) r.model_bytes += l.colours.byte_count() + l.features.size() * sizeof(int16_t);
    for (const auto& l : sets.levels) r.model_bytes += l.size() * sizeof(uint32_t);
    r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
    r.synthesise_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return r;
}

Image read_positions(const Image& example, PositionMap&& map, bool roll, int threads) {
    const int w = map.width, h = map.height;
    // Where to cut the torus open is free (coherent::torus_origin); the
    // change between two output pixels is read through their positions, the
    // same sums as on the pixels themselves.
    std::pair<int, int> origin{0, 0};
    if (roll) {
        const auto step = [&](int x0, int y0, int x1, int y1) {
            const uint32_t p0 = map.positions[std::size_t(y0) * w + x0], p1 = map.positions[std::size_t(y1) * w + x1];
            const uint8_t* a = example.at(position_x(p0), position_y(p0));
            const uint8_t* b = example.at(position_x(p1), position_y(p1));
            int d = 0;
            for (int c = 0; c < example.channels; ++c) d += std::abs(int(a[c]) - int(b[c]));
            return d;
        };
        origin = coherent::torus_origin(w, h, step);
    }
    const int ox = origin.first, oy = origin.second;
    // Output pixel (x, y) is the example's pixel at the position of (x + ox,
    // y + oy) on the torus, read through `index(i)` for map entry i.
    const auto read = [&](auto&& index) {
        Image out(w, h, example.channels);
        parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
            for (int y = int(y0); y < int(y1); ++y) {
                const std::size_t row = std::size_t(Image::wrap(y + oy, h)) * std::size_t(w);
                for (int x = 0; x < w; ++x)
                    copy_pixel(out.at(x, y), example.pixels.data() +
                                                 std::size_t(index(row + std::size_t(Image::wrap(x + ox, w)))) *
                                                     std::size_t(example.channels),
                               example.channels);
            }
        });
        return out;
    };
    const auto pixel_of = [&](uint32_t p) {
        return uint32_t(position_y(p)) * uint32_t(example.width) + uint32_t(position_x(p));
    };
    if (example.pixel_count() > 65536)
        return read([&](std::size_t i) { return pixel_of(map.positions[i]); });
    // A small example (an atlas of up to 256x256, the common case): its
    // pixel indices take 16 bits, so the positions are narrowed first and
    // let go before the output is allocated. Peak: the positions and the
    // narrow copy (6 bytes per output pixel), then the narrow copy and the
    // output, instead of the positions and the output (4 + channels bytes,
    // and the output's own copy in a cut torus besides).
    std::vector<uint16_t> narrow(map.positions.size());
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t i = y0 * std::size_t(w); i < y1 * std::size_t(w); ++i)
            narrow[i] = uint16_t(pixel_of(map.positions[i]));
    });
    std::vector<uint32_t>().swap(map.positions);
    return read([&](std::size_t i) { return narrow[i]; });
}

}  // namespace vqtex
