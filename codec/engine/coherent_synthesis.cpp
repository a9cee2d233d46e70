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
#include "engine/copy_links.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/seam_blend.hpp"
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
// A band's buffers when the finest level is synthesised in bands (band_rows),
// at most, and at least (band_bytes).
constexpr uint64_t kBandBytes = uint64_t(8) << 20;
constexpr uint64_t kMinBandBytes = uint64_t(2) << 20;

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
                       int link_bias, int edge_guard) {
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
    // The four nearest neighbours' taps (tap t is at offset t % kSide -
    // kRadius, t / kSide - kRadius from the pixel).
    static constexpr int kNearest[4] = {kTaps / 2 - kSide, kTaps / 2 - 1, kTaps / 2 + 1, kTaps / 2 + kSide};
    // No two adjacent pixels of the example share a position, so a
    // candidate that one of the four nearest neighbours holds would repeat a
    // pixel: it is not offered (k = 1). Without this rule, 1.4% of the
    // adjacent pixel pairs of a gravel output were repeats, against 0.07%
    // in its example.
    const auto repeats_a_neighbour = [&](uint32_t c) {
        for (int n : kNearest)
            if (c == sources[n]) return true;
        return false;
    };
    // Where a nearest neighbour's copy would go on past the example's edge
    // (format 7's edge guard), a position just inside that point would show
    // the copy's last columns or rows again beside themselves, a stutter:
    // it is not offered either (any k), so that the copy ends in a seam.
    int cut_x[4], cut_y[4], cuts = 0;
    if (edge_guard > 0 && !v.space.wraps)
        for (int t : kNearest) {
            const ShiftedSource c = shifted_source(position_x(sources[t]), position_y(sources[t]), t % kSide - kRadius,
                                                   t / kSide - kRadius, v.spacing);
            if (c.x < 0 || c.y < 0 || c.x >= v.space.width || c.y >= v.space.height) {
                cut_x[cuts] = c.x;
                cut_y[cuts++] = c.y;
            }
        }
    const auto beside_a_cut = [&](uint32_t c) {
        for (int i = 0; i < cuts; ++i)
            if (std::abs(position_x(c) - cut_x[i]) < edge_guard && std::abs(position_y(c) - cut_y[i]) < edge_guard)
                return true;
        return false;
    };
    const auto barred = [&](uint32_t c) { return repeats_a_neighbour(c) || beside_a_cut(c); };
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
            if (c != own_position && !barred(c)) candidates.add(c, true);
            continue;
        }
        const uint32_t* set = v.sets.of(v.level, uint32_t(uy) * uint32_t(ex_w) + uint32_t(ux));
        for (int i = 0; i < k; ++i) {
            const uint32_t c = pack_position(int(set[i] % uint32_t(ex_w)), int(set[i] / uint32_t(ex_w)));
            if (!beside_a_cut(c)) candidates.add(c, i == 0);
        }
    }
    const int count = candidates.size();
    // Inside a coherent copy every neighbour proposes the pixel's own
    // position: nothing to compare.
    if (count == 0) return own_position;
    alignas(32) int16_t query[kTaps * kAppearanceDims];
    for (int t = 0; t < kTaps; ++t)
        std::memcpy(query + t * kAppearanceDims, v.feature(sources[t]), sizeof(int16_t) * kAppearanceDims);
    // The pixel's own position competes too, first and unbiased (its source
    // may be off the example's edge for every neighbour); unless it is
    // barred (it repeats a neighbour's, or lies beside a cut), when any
    // candidate takes its place; with none, it stays.
    // Each of the four nearest neighbours that does not continue a
    // candidate's copy surcharges its distance by `link_bias`: a position
    // that sits inside one copy with its neighbours beats one that a
    // single neighbour proposes. This is what breaks up combs, patches
    // whose alternate rows or columns hold two different copies, where every
    // pixel sees its own copy on two sides and the other on two.
    const auto surcharge = [&](uint32_t c) {
        const int cx = position_x(c), cy = position_y(c), s = v.spacing;
        int links = 0;
        for (int t : kNearest)
            links += int(sources[t] == pack_position(cx + (t % kSide - kRadius) * s, cy + (t / kSide - kRadius) * s));
        return uint64_t(256) + uint64_t(link_bias) * uint64_t(4 - links);
    };
    const auto scaled = [](uint64_t d, uint64_t factor) { return uint32_t(std::min<uint64_t>(UINT32_MAX, d * factor / 256)); };
    uint32_t best = own_position;
    uint32_t best_d = barred(own_position)
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

// Clears the revisit flag of every pixel whose correction would keep its
// position at once: with k = 1, a pixel whose source lies at least the
// window's reach inside the example and whose whole window continues it
// (correct_pixel's first check, proposing == 0). That is most of a level
// (83% of the finest level's pixels on stk_granite, in each of its two
// passes), and checking a window there costs 25 gathered positions and a
// call per pixel. Here it is found for the whole map from the links
// between adjacent pixels, a few byte operations a pixel that vectorise:
// the window continues its centre at every tap if and only if each pixel
// continues its left neighbour along the window's rows (20 links) and
// its upper neighbour down the centre column (4), the differences of packed
// positions being additive (mod 2^32; exact inside the example, which the
// centre's reach guarantees). Skipped pixels keep the position a
// correction would have given them, so the bytes are the same; a later
// change in a window marks it due again (interleaved_pass).
void skip_coherent(const LevelView& v, const PositionMap& map, coherent::Revisit& revisit,
                   const coherent::Band* band, int threads) {
    const int w = map.width, h = map.height;
    const int reach = kRadius * v.spacing;
    if (v.k != 1 || w < kSide || h < kSide || v.space.width <= 2 * reach || v.space.height <= 2 * reach) return;
    const uint32_t* pos = map.positions.data();
    const uint32_t step_x = uint32_t(v.spacing), step_y = uint32_t(v.spacing) << 16;
    const uint32_t inside_x = uint32_t(v.space.width - 2 * reach), inside_y = uint32_t(v.space.height - 2 * reach);
    // A band's windows in its first and last kRadius rows read clamped rows
    // (a row twice), which never continue: those stay due.
    const int first = band ? kRadius : 0, last = band ? h - kRadius : h;
    if (first >= last) return;
    const auto row_at = [&](int y) { return pos + std::size_t(band ? y : Image::wrap(y, h)) * std::size_t(w); };
    parallel_for(threads, std::size_t(last - first), 32, [&](std::size_t r0, std::size_t r1) {
        const int y0 = first + int(r0), y1 = first + int(r1);
        const int rows = y1 - y0 + 2 * kRadius;  // rows y0 - kRadius .. y1 + kRadius - 1
        // Per local row i (row y0 - kRadius + i): its runs, and the down
        // links from it to row i + 1.
        std::vector<uint8_t> runs(std::size_t(rows) * w), down(std::size_t(rows - 1) * w),
            links(std::size_t(w) + 2 * kRadius), whole(static_cast<std::size_t>(w));
        for (int i = 0; i < rows; ++i) {
            const uint32_t* row = row_at(y0 - kRadius + i);
            coherent::window_runs(row, w, kRadius, step_x, links.data(), runs.data() + std::size_t(i) * w);
            if (i + 1 < rows)
                coherent::window_down(row, row_at(y0 - kRadius + i + 1), w, step_y, down.data() + std::size_t(i) * w);
        }
        for (int y = y0; y < y1; ++y) {
            coherent::whole_windows(pos + std::size_t(y) * w, runs.data() + std::size_t(y - y0) * w,
                                    down.data() + std::size_t(y - y0) * w, w, kRadius, uint32_t(reach), inside_x,
                                    inside_y, whole.data());
            uint8_t* due = revisit.due.data() + std::size_t(y) * w;
            for (int x = 0; x < w; ++x) due[x] &= uint8_t(whole[std::size_t(x)] ^ 1);
        }
    });
}

// One correction pass over the whole level, or over a band of its rows
// (coherent::interleaved_pass).
void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options,
                     coherent::Revisit* revisit = nullptr, const coherent::Band* band = nullptr) {
    const int w = map.width;
    coherent::interleaved_pass(
        options.threads, map.width, map.height, map.positions,
        [&](int, int, const int* xs, const int* ys) {
            return correct_pixel(view, map.positions.data(), w, xs, ys, options.coherence_bias, options.link_bias,
                                 options.edge_guard);
        },
        revisit, band);
}

// Rows [first, first + count) of a width x height level, wrapped on its
// height, before correction: each child takes its parent's position
// (`parent_at(i)` for entry i of the parent map, `parent_width` wide) plus
// its offset times `spacing`, then with `jitter` the level's seeded
// displacement. Each pixel's start depends on nothing else, so a band of
// rows starts as the same rows of the whole level.
template <typename ParentAt>
void start_rows(const AppearanceSpace& space, ParentAt&& parent_at, int parent_width, int width, int height,
                int level, int spacing, const CoherentOptions& options, bool jitter, int first, int count,
                uint32_t* out) {
    // Jitter of up to jitter/256 of the spacing in x and y.
    const int64_t reach = jitter ? int64_t(spacing) * options.jitter : 0;
    // Format 7: children past the example's edge clamped (child_coordinate).
    const bool clamp = options.edge_guard > 0;
    parallel_for(options.threads, std::size_t(count), 16, [&](std::size_t r0, std::size_t r1) {
        for (int r = int(r0); r < int(r1); ++r) {
            const int y = (first + r) % height;
            uint32_t* row = out + std::size_t(r) * std::size_t(width);
            for (int x = 0; x < width; ++x) {
                const uint32_t p = parent_at(std::size_t(y >> 1) * std::size_t(parent_width) + std::size_t(x >> 1));
                row[x] = pack_position(
                    coherent::child_coordinate(space.width, space.wraps, position_x(p), x & 1, spacing, clamp),
                    coherent::child_coordinate(space.height, space.wraps, position_y(p), y & 1, spacing, clamp));
                if (reach > 0) {
                    const uint64_t hash = pixel_hash(options.seed, level, 1, x, y);
                    const int64_t jx = ((int64_t(hash & 0xFFFF) - 32768) * reach) / (32768 * 256);
                    const int64_t jy = ((int64_t((hash >> 16) & 0xFFFF) - 32768) * reach) / (32768 * 256);
                    row[x] = folded(space, position_x(row[x]) + int(jx), position_y(row[x]) + int(jy));
                }
            }
        }
    });
}

// Correction passes at each level, counted for the progress callback.
struct LevelPasses {
    const AppearanceSpace& space;
    const CoherenceSets& sets;
    const CoherentOptions& options;
    int top;
    uint64_t done = 0, total = 0;
    // When the analysis is made level by level: the space and sets above,
    // whose levels enter() fills and empties (otherwise null).
    AppearanceSpace* by_level_space = nullptr;
    CoherenceSets* by_level_sets = nullptr;

    LevelPasses(const AppearanceSpace& s, const CoherenceSets& c, const CoherentOptions& o)
        : space(s), sets(c), options(o), top(int(s.levels.size()) - 1) {
        for (int l = top; l >= 0; --l) {
            const uint64_t area = uint64_t(pyramid_level_size(options.width, l)) * pyramid_level_size(options.height, l);
            total += area * uint64_t(passes_at(l));
        }
    }

    // The finest level runs one pass fewer: the colour polish follows it,
    // and with the link bias its second pass changed the corpus scores by
    // under 0.5% for a tenth of the synthesis time (SYNTHESIS.md).
    int passes_at(int l) const {
        return l == top ? options.coarse_passes : l == 0 ? std::max(1, options.passes - 1) : options.passes;
    }

    // Before level l's passes when the analysis is made level by level:
    // the coarser level's vectors and sets are let go, then l's are made
    // (one level's at a time).
    void enter(int l) {
        if (!by_level_space) return;
        if (l < top) {
            std::vector<int16_t>().swap(by_level_space->levels[std::size_t(l + 1)].features);
            std::vector<uint32_t>().swap(by_level_sets->levels[std::size_t(l + 1)]);
        }
        build_level_features(*by_level_space, l, options.threads);
        by_level_sets->levels[std::size_t(l)] =
            build_level_coherence_sets(*by_level_space, l, by_level_sets->k, kCoherenceExclusion, options.threads);
        // The level's stack colours served only to make its vectors (the
        // finest level's are the example's, whose channel count the
        // vectors' making reads).
        if (l > 0) by_level_space->levels[std::size_t(l)].colours = Image();
    }

    // Rows from a band's edges that the finest level's passes may leave
    // wrong: 2 more than its subsets, four a pass (coherent::Band).
    // With a blend, its radius more: a band's own pixels read the map that
    // far past them.
    int band_margin() const {
        return 4 * (passes_at(0) + std::max(0, options.polish_passes)) + 2 + std::clamp(options.blend, 0, kMaxBlendRadius);
    }

    // Level l's passes on `map` (the whole level, or with `band` some of its
    // rows, of which `own_rows` count for progress), then at the finest
    // level the colour polish.
    void run(int l, PositionMap& map, const coherent::Band* band = nullptr, int own_rows = 0) {
        const int spacing = space.levels[std::size_t(l)].spacing;
        const LevelView view{space, sets, l, spacing, space.levels[std::size_t(l)].features.data(), sets.k,
                             dsp::kernels()};
        coherent::Revisit revisit(map.positions.size());
        for (int pass = 0; pass < passes_at(l); ++pass) {
            skip_coherent(view, map, revisit, band, options.threads);
            correction_pass(view, map, options, &revisit, band);
            done += uint64_t(map.width) * uint64_t(band ? own_rows : map.height);
            if (options.progress && !options.progress(done, total))
                fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        if (!band && l >= kRelocationMinLevel) relocate_copies(space, l, map, options.relocate, options.seed, options.threads);
        if (l == 0 && options.polish_passes > 0) {
            // Seams between coherent copies are placed by colours at last:
            // the coherence of the output's own pixels is what a viewer sees.
            // Every pixel is due again (other features); the flags of the
            // level's passes are reused rather than a second set allocated
            // beside them (a byte per output pixel).
            const LevelView polish{space, sets, 0, 1, space.pixels.data(), 1, dsp::kernels()};
            std::fill(revisit.due.begin(), revisit.due.end(), uint8_t(1));
            for (int pass = 0; pass < options.polish_passes; ++pass) {
                skip_coherent(polish, map, revisit, band, options.threads);
                correction_pass(polish, map, options, &revisit, band);
            }
        }
    }

    // Levels from the coarsest down to `last`, whole.
    PositionMap levels_down_to(int last) {
        PositionMap map;
        for (int l = top; l >= last; --l) {
            enter(l);
            const int w = pyramid_level_size(options.width, l), h = pyramid_level_size(options.height, l);
            if (l == top) {
                // The coarsest level starts anywhere: positions drawn at random.
                map = PositionMap{w, h, std::vector<uint32_t>(std::size_t(w) * h)};
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const uint64_t r = pixel_hash(options.seed, l, 0, x, y);
                        map.positions[std::size_t(y) * w + x] = pack_position(
                            int((r & 0xFFFFFFFF) % uint64_t(space.width)), int((r >> 32) % uint64_t(space.height)));
                    }
            } else {
                PositionMap child{w, h, std::vector<uint32_t>(std::size_t(w) * h)};
                start_rows(space, [&](std::size_t i) { return map.positions[i]; }, map.width, w, h, l,
                           space.levels[std::size_t(l)].spacing, options, true, 0, h, child.positions.data());
                map = std::move(child);
            }
            run(l, map);
        }
        return map;
    }
};

// Output rows per band of the finest level, or 0 to synthesise it whole.
// Whole, the level's buffers take 6.25 bytes a pixel (positions, revisit
// flags, a subset's choices, and a quarter of a byte for which of those
// changed): within twice the output plus 8 MiB from 4 channels, and from 3
// up to about 5800x5800, so those outputs and small ones keep the single
// pass over the level. With a blend, reading it holds the positions and the
// output, 4 + channels bytes a pixel: 3 channels stay whole up to about
// 2900x2900. Otherwise bands of about 8 MiB of buffers: a band, the output
// and the coarser level (its pixel indices: 0.5 or 0.75 bytes an output
// pixel for an atlas, PixelIndices) stay within
// twice the output plus 16 MiB (issue 17's budget), and so does the output
// with the caller's copy of it beside a band's worth of freed memory that
// the allocator may keep. Each band's `margin` rows on either side are
// synthesised twice.
int band_rows(const CoherentOptions& options, int channels, int margin, uint64_t band_bytes) {
    const uint64_t pixels = uint64_t(options.width) * uint64_t(options.height);
    int rows = options.band_rows;
    if (rows <= 0) {
        // In quarter bytes: 25 a pixel whole, or 4 (4 + channels) to read a blend.
        const uint64_t whole = options.blend > 0 ? std::max<uint64_t>(25, 4 * (4 + uint64_t(channels))) : 25;
        if (whole * pixels <= 4 * (2 * pixels * uint64_t(channels) + band_bytes)) return 0;
        const uint64_t with_margins = 4 * band_bytes / (25 * uint64_t(options.width));
        rows = int(std::min<uint64_t>(std::max<uint64_t>(with_margins, 4 * uint64_t(margin)) - 2 * uint64_t(margin),
                                      uint64_t(options.height)));
    }
    return uint64_t(rows) + 2 * uint64_t(margin) < uint64_t(options.height) ? rows : 0;
}

// Cuts the w x h torus of `image` open at (ox, oy) in place: pixel (x, y)
// becomes the one at (x + ox, y + oy). Rows move along the cycles of the
// turn by oy, each copied once, turned by ox on the way, with one row held
// aside per cycle: no second image.
void roll_in_place(Image& image, int ox, int oy) {
    const std::size_t pixel = std::size_t(image.channels), row_bytes = std::size_t(image.width) * pixel;
    const std::size_t head = std::size_t(ox) * pixel, tail = row_bytes - head;
    const int h = image.height;
    if (ox == 0 && oy == 0) return;
    const auto row = [&](int y) { return image.pixels.data() + std::size_t(y) * row_bytes; };
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

// The sum of |a[i] - b[i]| over n bytes.
uint32_t byte_distance(const uint8_t* __restrict a, const uint8_t* __restrict b, std::size_t n) {
    uint32_t d = 0;
    for (std::size_t i = 0; i < n; ++i) d += uint32_t(std::abs(int(a[i]) - int(b[i])));
    return d;
}

// acc[i - first] += |row[i] - row[i - channels]| for i in [first, last).
void add_steps(const uint8_t* __restrict row, std::size_t first, std::size_t last, std::size_t channels,
               uint32_t* __restrict acc) {
    for (std::size_t i = first; i < last; ++i) acc[i - first] += uint32_t(std::abs(int(row[i]) - int(row[i - channels])));
}

// Cuts the torus of `image` open in place where its pixels change least:
// coherent::torus_origin's choice, with the change between two pixels the
// sum of their channels' differences. The sums are taken on the bytes as
// they lie (a row against the one above; a row against itself a pixel
// on, in strips of columns), which vectorise: through the positions, a
// pixel at a time, they were 5% of a 512x512 decode. The same integers,
// so the same cut.
void cut_torus(Image& image, int threads) {
    const int w = image.width, h = image.height;
    const std::size_t ch = std::size_t(image.channels), row_bytes = std::size_t(w) * ch;
    std::vector<int64_t> across_x(std::size_t(w), 0), across_y(std::size_t(h), 0);
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t y = y0; y < y1; ++y)
            across_y[y] = byte_distance(image.at(0, y == 0 ? h - 1 : int(y) - 1), image.at(0, int(y)), row_bytes);
    });
    constexpr int kStrip = 256;
    parallel_for(threads, std::size_t((w + kStrip - 1) / kStrip), 1, [&](std::size_t s0, std::size_t s1) {
        const int x0 = int(s0) * kStrip, x1 = std::min(w, int(s1) * kStrip);
        std::vector<uint32_t> acc(std::size_t(x1 - x0) * ch, 0);  // per byte of the strip
        for (int y = 0; y < h; ++y) {
            const uint8_t* row = image.at(0, y);
            // Column 0 steps from the last column (the wrap).
            if (x0 == 0)
                for (std::size_t c = 0; c < ch; ++c) acc[c] += uint32_t(std::abs(int(row[c]) - int(row[row_bytes - ch + c])));
            add_steps(row, std::size_t(std::max(x0, 1)) * ch, std::size_t(x1) * ch, ch,
                      acc.data() + (x0 == 0 ? ch : 0));
        }
        for (int x = x0; x < x1; ++x) {
            int64_t sum = 0;
            for (std::size_t c = 0; c < ch; ++c) sum += acc[std::size_t(x - x0) * ch + c];
            across_x[std::size_t(x)] = sum;
        }
    });
    const std::pair<int, int> origin = coherent::least_change_origin(across_x, across_y);
    roll_in_place(image, origin.first, origin.second);
}

// The output of a large texture: the finest level synthesised in bands of
// `band` rows, each with `margin` rows more on either side (the rows the
// band's passes leave wrong), from the coarser level's positions; each
// band's own rows are read into the output at once, so neither the finest
// level's positions nor a second image are ever whole. The same bytes as
// read_positions on the whole level: a band's rows are exact, and the torus
// cut is found on the pixels, the same sums as through the positions.
Image synthesize_in_bands(const Image& example, LevelPasses& passes, int band, int margin) {
    const CoherentOptions& options = passes.options;
    const AppearanceSpace& space = passes.space;
    const int w = options.width, h = options.height;
    PositionMap coarse = passes.levels_down_to(1);
    // The coarser level as pixel indices (2 or 3 bytes each for an atlas,
    // PixelIndices), as read_positions narrows the finest.
    PixelIndices parents = narrow_positions(example.width, example.pixel_count(), coarse.positions, options.threads);
    const auto parent_at = [&](std::size_t i) { return parents.position(i); };
    Image out(w, h, example.channels);
    PositionMap part{w, 0, {}};
    passes.enter(0);
    for (int y0 = 0; y0 < h; y0 += band) {
        const int rows = std::min(band, h - y0);
        const coherent::Band rows_of{Image::wrap(y0 - margin, h), h};
        part.height = rows + 2 * margin;
        part.positions.resize(std::size_t(w) * std::size_t(part.height));
        start_rows(space, parent_at, coarse.width, w, h, 0, space.levels[0].spacing, options, true, rows_of.first,
                   part.height, part.positions.data());
        passes.run(0, part, &rows_of, rows);
        // The band's own rows (blend 0 copies each pixel).
        blend_rows(example, space.wraps, options.blend,
                   [&](int y) { return part.positions.data() + std::size_t(y - y0 + margin) * std::size_t(w); }, y0,
                   rows, out, options.threads);
    }
    std::vector<uint32_t>().swap(part.positions);
    std::vector<uint8_t>().swap(parents.data);
    if (options.roll) cut_torus(out, options.threads);
    return out;
}

// A band's buffers: 8 MiB, less what the analysis holds beyond 4 MiB (an
// atlas of more than 65536 pixels: a 512x512 grey one of 8 levels is
// counted 10 MiB, so 2 MiB bands), down to 2 MiB, so that the whole decode stays within twice the output plus 16
// MiB. The band's size changes no byte of the output.
uint64_t band_bytes(const Image& example, const AppearanceSpace& space, int coherence) {
    const uint64_t held = coherent_analysis_memory(example.width, example.height, example.channels,
                                                   int(space.levels.size()), coherence);
    const uint64_t spare = kBandBytes + kAnalysisAtOnceBytes;
    return held >= spare - kMinBandBytes ? kMinBandBytes : std::min(kBandBytes, spare - held);
}

// The output: the finest level whole and read through its positions, or
// for a large output in bands.
Image synthesize_pixels(const Image& example, const AppearanceSpace& space, const CoherenceSets& sets,
                        const CoherentOptions& options, AppearanceSpace* by_level_space = nullptr,
                        CoherenceSets* by_level_sets = nullptr) {
    LevelPasses passes(space, sets, options);
    passes.by_level_space = by_level_space;
    passes.by_level_sets = by_level_sets;
    const int margin = passes.band_margin();
    const int band = band_rows(options, example.channels, margin, band_bytes(example, space, sets.k));
    if (band == 0)
        return read_positions(example, passes.levels_down_to(0), options.roll, options.threads, options.blend,
                              space.wraps);
    return synthesize_in_bands(example, passes, band, margin);
}

}  // namespace

PixelIndices narrow_positions(int example_width, uint64_t example_pixels, std::vector<uint32_t>& positions,
                              int threads) {
    PixelIndices out;
    out.bytes = PixelIndices::bytes_for(example_pixels);
    out.example_width = example_width;
    out.data.resize(positions.size() * std::size_t(out.bytes));
    const std::size_t bytes = std::size_t(out.bytes);
    parallel_for(threads, positions.size(), 4096, [&](std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
            const uint32_t index = uint32_t(position_y(positions[i])) * uint32_t(example_width) +
                                   uint32_t(position_x(positions[i]));
            for (std::size_t b = 0; b < bytes; ++b) out.data[i * bytes + b] = uint8_t(index >> (8 * b));
        }
    });
    std::vector<uint32_t>().swap(positions);
    return out;
}

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
    CoherentOptions options;
    options.threads = threads;
    start_rows(space, [&](std::size_t i) { return parent.positions[i]; }, parent.width, width, height, 0, spacing,
               options, false, 0, height, out.positions.data());
    return out;
}

PositionMap synthesize_positions(const AppearanceSpace& space, const CoherenceSets& sets,
                                 const CoherentOptions& options) {
    LevelPasses passes(space, sets, options);
    return passes.levels_down_to(0);
}

uint64_t coherent_output_memory(uint64_t width, uint64_t height, int channels) {
    // Whole: max(6.25, 4 + channels, 2 x channels) bytes a pixel. In bands
    // (from 6 > 2 x channels bytes a pixel only): at most 1 + channels + 6
    // with the band (whose change flags add a 24th to kBandBytes), or 2 x
    // channels + 6 at the end, plus kBandBytes: within the 6 + 2 x channels
    // bytes a pixel counted.
    return width * height * (6 + 2 * uint64_t(channels)) + kBandBytes;
}

bool analysis_by_level(int width, int height, int levels) {
    return uint64_t(width) * uint64_t(height) * uint64_t(std::max(levels, 0)) * kAppearanceDims * sizeof(int16_t) >
           kAnalysisAtOnceBytes;
}

uint64_t coherent_analysis_memory(int width, int height, int channels, int levels, int coherence) {
    const uint64_t n = uint64_t(width) * uint64_t(height), l = uint64_t(std::max(levels, 0));
    // A level's appearance vectors, and its coherence sets for k > 1.
    const uint64_t level = n * (kAppearanceDims * sizeof(int16_t) + (coherence > 1 ? 4 * uint64_t(coherence) : 0));
    // The stack's colours (its finest level is a copy of the example) and
    // the raw-colour vectors, then the levels held at once; for k > 1 also
    // the sort order and ranks of the level whose sets are being built.
    return n * (l * uint64_t(channels) + kAppearanceDims * sizeof(int16_t) + (coherence > 1 ? 8 : 0)) +
           (analysis_by_level(width, height, levels) ? level : l * level);
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
    if (example.width > VQTEX_MAX_SIDE || example.height > VQTEX_MAX_SIDE)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED,
             "example larger than " + std::to_string(VQTEX_MAX_SIDE) + " pixels on a side");
    const auto t0 = Clock::now();
    if (analyse_progress && !analyse_progress(0, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const bool by_level = options.analysis_by_level < 0 ? analysis_by_level(example.width, example.height, levels)
                                                        : options.analysis_by_level > 0;
    AppearanceSpace space = build_appearance_space(example, levels, example_tileable, options.threads, !by_level);
    CoherenceSets sets;
    if (by_level) {
        sets.k = std::max(coherence, 1);
        sets.levels.resize(space.levels.size());
    } else {
        sets = build_coherence_sets(space, coherence, kCoherenceExclusion, options.threads);
    }
    if (analyse_progress && !analyse_progress(1, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const auto t1 = Clock::now();
    CoherentResult r;
    r.image = synthesize_pixels(example, space, sets, options, by_level ? &space : nullptr, by_level ? &sets : nullptr);
    // What the analysis makes, whether it is held at once or level by level.
    const uint64_t n = example.pixel_count();
    r.model_bytes = space.levels.size() * (example.byte_count() + n * kAppearanceDims * sizeof(int16_t));
    if (sets.k > 1) r.model_bytes += space.levels.size() * n * uint64_t(sets.k) * sizeof(uint32_t);
    r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
    r.synthesise_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return r;
}

Image read_positions(const Image& example, PositionMap&& map, bool roll, int threads, int blend, bool wraps) {
    const int w = map.width, h = map.height;
    if (blend > 0 || PixelIndices::bytes_for(example.pixel_count()) > 2) {
        // Read through the packed positions, which the blend's window
        // check needs (blend 0 copies each pixel): 4 + channels bytes a
        // pixel at the peak.
        Image out(w, h, example.channels);
        blend_rows(example, wraps, blend,
                   [&](int y) { return map.positions.data() + std::size_t(Image::wrap(y, h)) * std::size_t(w); }, 0, h,
                   out, threads);
        std::vector<uint32_t>().swap(map.positions);
        if (roll) cut_torus(out, threads);
        return out;
    }
    // A small example and no blend: the positions are narrowed to 2-byte
    // indices first and let go before the output is allocated. Peak: the
    // positions and the narrow copy (6 bytes per output pixel), then the
    // narrow copy and the output, instead of the positions and the output
    // (4 + channels bytes). Then the torus is cut open where its pixels
    // change least (the same cut as one found through the positions).
    const std::size_t channels = std::size_t(example.channels);
    const PixelIndices narrow = narrow_positions(example.width, example.pixel_count(), map.positions, threads);
    Image out(w, h, example.channels);
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t i = y0 * std::size_t(w); i < y1 * std::size_t(w); ++i)
            copy_pixel(out.pixels.data() + i * channels, example.pixels.data() + std::size_t(narrow.index(i)) * channels,
                       example.channels);
    });
    if (roll) cut_torus(out, threads);
    return out;
}

}  // namespace vqtex
