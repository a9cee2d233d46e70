// coherent_pixel_correction.cpp - the still engine's correction of pixel
// positions with k-coherence candidates in appearance space (Lefebvre &
// Hoppe 2005 section 3.4, 2006 section 4; Tong et al. 2002; Ashikhmin
// 2001). See coherent_pixel_correction.hpp.
#include "engine/coherent_pixel_correction.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <vector>

#include "common/parallel.hpp"
#include "dsp/vector_distance.hpp"
#include "engine/coherent_candidates.hpp"
#include "engine/coherent_correction.hpp"
#include "engine/copy_links.hpp"
#include "engine/coherent_start.hpp"

namespace vqtex::coherent {
namespace {

// Whether position c at (x, y) of a map w wide would show the example again
// a whole number of periods (px across, py down; 0: none) to the right of
// or below a pixel before it, or one period on along either diagonal
// (down and to the right or left): the period bar bars the later of two
// such pixels, so that the first keeps its copy. Without the diagonals,
// copies kept off the axes lined up along them (a 2x2 output showing one
// copy in two opposite quarters).
bool repeats_period(const uint32_t* map, int w, int x, int y, int px, int py, uint32_t c) {
    const auto holds = [&](int bx, int by) { return map[std::size_t(by) * std::size_t(w) + std::size_t(bx)] == c; };
    for (int before = x - px; px > 0 && before >= 0; before -= px)
        if (holds(before, y)) return true;
    for (int before = y - py; py > 0 && before >= 0; before -= py)
        if (holds(x, before)) return true;
    if (px > 0 && py > 0 && y >= py) {
        if (x >= px && holds(x - px, y - py)) return true;
        if (x + px < w && holds(x + px, y - py)) return true;
    }
    return false;
}

// The four nearest neighbours' taps.
constexpr int kNearest[4] = {kTaps / 2 - kSide, kTaps / 2 - 1, kTaps / 2 + 1, kTaps / 2 + kSide};

// The still engine's correction step (coherent::correct) of a pixel of
// `cur` (w wide, a torus): the best of its neighbours' coherent candidates.
struct PixelStep {
    using Position = uint32_t;
    using Distance = uint32_t;
    static constexpr int kMaxCandidates = kTaps * 16;
    static constexpr int kWindows = 1;
    struct Window {
        uint32_t sources[kTaps];
        // Where a nearest neighbour's copy would go on past the example's
        // edge (the edge guard's cuts).
        int cut_x[4], cut_y[4], cuts = 0;
        int cx = 0, cy = 0;     // the pixel's place in the map
        bool periodic = false;  // its own position is barred (repeats_period)
        uint32_t own() const { return sources[kTaps / 2]; }
    };

    const LevelView& v;
    const uint32_t* cur;
    int w;
    int bias, link_bias, edge_guard;
    // The period bar's periods in the level's pixels (level_period; 0:
    // none), and the seed of the positions it offers.
    int period_x = 0, period_y = 0;
    uint64_t seed = 0;

    bool repeats_period(const Window& win, uint32_t c) const {
        return coherent::repeats_period(cur, w, win.cx, win.cy, period_x, period_y, c);
    }
    void gather(const int* xs, const int* ys, Window& win) const {
        gather_window(cur, w, xs, ys, win.sources);
        win.cx = xs[kRadius];
        win.cy = ys[kRadius];
        win.periodic = (period_x > 0 || period_y > 0) && repeats_period(win, win.own());
    }
    // With k = 1 a pixel inside its neighbours' copy has nothing to compare.
    bool settled(const Window& win, uint32_t& departing) const {
        if (win.periodic) {
            departing = kAllTaps;
            return false;
        }
        departing = departing_taps<PixelPositions>(v.space, v.spacing, win.sources, win.own());
        return departing == 0 && v.k == 1;
    }
    // No two adjacent pixels of the example share a position, so a
    // candidate that one of the four nearest neighbours holds would repeat a
    // pixel: it is not offered (k = 1). Without this rule, 1.4% of the
    // adjacent pixel pairs of a gravel output were repeats, against 0.07%
    // in its example.
    bool repeats_a_neighbour(const Window& win, uint32_t c) const {
        for (int n : kNearest)
            if (c == win.sources[n]) return true;
        return false;
    }
    bool beside_a_cut(const Window& win, uint32_t c) const {
        for (int i = 0; i < win.cuts; ++i)
            if (std::abs(position_x(c) - win.cut_x[i]) < edge_guard && std::abs(position_y(c) - win.cut_y[i]) < edge_guard)
                return true;
        return false;
    }
    bool barred(const Window& win, uint32_t c) const {
        return repeats_a_neighbour(win, c) || beside_a_cut(win, c) || (win.periodic && repeats_period(win, c));
    }
    template <typename List>
    void propose(Window& win, uint32_t departing, List& candidates) const {
        // Where a nearest neighbour's copy would go on past the example's
        // edge (the edge guard), a position just inside that point would
        // show the copy's last columns or rows again beside themselves, a
        // stutter: it is not offered either (any k), so that the copy ends
        // in a seam.
        if (edge_guard > 0 && !v.space.wraps)
            for (int t : kNearest) {
                const ShiftedSource c =
                    shifted_source(position_x(win.sources[t]), position_y(win.sources[t]), tap_dx(t), tap_dy(t), v.spacing);
                if (c.x < 0 || c.y < 0 || c.x >= v.space.width || c.y >= v.space.height) {
                    win.cut_x[win.cuts] = c.x;
                    win.cut_y[win.cuts++] = c.y;
                }
            }
        const uint32_t own = win.own();
        // A pixel the period bar moves needs a position no neighbour offers
        // where it sits inside one copy with them: one drawn at random
        // (seeded, per pixel), which its neighbours then continue.
        if (win.periodic) {
            const uint32_t c =
                random_position(pixel_hash(seed, v.level, kPeriodPurpose, win.cx, win.cy), v.space.width, v.space.height);
            if (!barred(win, c)) candidates.add(c, false);
        }
        const int k = std::min(v.k, kMaxCandidates / kTaps);
        const uint32_t ex_w = uint32_t(v.space.width);
        // With k = 1 only the departing neighbours are visited: a neighbour
        // that continues the pixel's own copy proposes the pixel's own
        // position, which is evaluated first anyway.
        for (uint32_t taps = k == 1 ? departing : kAllTaps; taps != 0; taps &= taps - 1) {
            const int t = __builtin_ctz(taps);
            int ux, uy;
            if (!continued_source(v.space, v.spacing, position_x(win.sources[t]), position_y(win.sources[t]), t, ux, uy))
                continue;  // the neighbour's source continues past the example's edge
            if (k == 1) {
                const uint32_t c = pack_position(ux, uy);
                if (c != own && !barred(win, c)) candidates.add(c, true);
                continue;
            }
            // Tong et al.'s k-coherence: the proposal's k - 1 most similar
            // positions after it, which continue no neighbour's copy.
            const uint32_t* set = v.sets.of(v.level, uint32_t(uy) * ex_w + uint32_t(ux));
            for (int i = 0; i < k; ++i) {
                const uint32_t c = pack_position(int(set[i] % ex_w), int(set[i] / ex_w));
                if (!beside_a_cut(win, c)) candidates.add(c, i == 0);
            }
        }
    }
    void fill_query(const Window& win, int16_t* query) const {
        coherent::fill_query(win.sources, [&](uint32_t p) { return v.feature(p); }, query);
    }
    // Each of the four nearest neighbours that does not continue a
    // candidate's copy surcharges its distance by `link_bias`: a position
    // that sits inside one copy with its neighbours beats one that a
    // single neighbour proposes. This is what breaks up combs, patches
    // whose alternate rows or columns hold two different copies, where every
    // pixel sees its own copy on two sides and the other on two. An
    // alternative that continues no neighbour's copy must beat the best by
    // the coherence bias besides: d (1 + bias/256) < best.
    uint64_t weight(const Window& win, uint32_t c, bool continues) const {
        const int cx = position_x(c), cy = position_y(c), s = v.spacing;
        int links = 0;
        for (int t : kNearest) links += int(win.sources[t] == pack_position(cx + tap_dx(t) * s, cy + tap_dy(t) * s));
        return (uint64_t(256) + uint64_t(link_bias) * uint64_t(4 - links)) * (continues ? 256 : uint64_t(256 + bias));
    }
    uint32_t distance(const Window&, const int16_t* query, uint32_t c, uint32_t bound) const {
        return v.distance(query, position_x(c), position_y(c), bound);
    }
    // The own position's window holds the query's own vector at every tap
    // that continues it, so only settled's departing taps add to its
    // distance (all taps are departing where the window reaches past the
    // example's edge and folds: there the whole window is compared). The
    // sums stay below 2^32 (25 taps of clamped vectors): the same as the
    // whole window's.
    uint32_t own_distance(const Window& win, const int16_t* query, uint32_t departing) const {
        const uint32_t own = win.own();
        if (departing == kAllTaps)
            return v.distance(query, position_x(own), position_y(own), std::numeric_limits<uint32_t>::max());
        uint32_t total = 0;
        for (uint32_t taps = departing; taps != 0; taps &= taps - 1) {
            const int t = __builtin_ctz(taps);
            total += uint32_t(dsp::vector_distance(
                query + t * kAppearanceDims,
                v.feature(position_x(own) + tap_dx(t) * v.spacing, position_y(own) + tap_dy(t) * v.spacing)));
        }
        return total;
    }
};

}  // namespace

LevelView level_view(const AppearanceSpace& space, const CoherenceSets& sets, int level) {
    return LevelView{space,  sets,  level, space.levels[std::size_t(level)].spacing,
                     space.levels[std::size_t(level)].features.data(), sets.k, dsp::kernels()};
}

LevelView polish_view(const AppearanceSpace& space, const CoherenceSets& sets) {
    return LevelView{space, sets, 0, 1, space.pixels.data(), 1, dsp::kernels()};
}

// The example's period in the level's pixels, across and down (0: none),
// where the period bar applies: a wrapping example, a level above the
// finest (never in bands), a spacing that divides the example's side and
// an output of more than one period. At the finest level the copies keep
// the extents the coarser levels gave them, give or take the few pixels a
// correction moves a border.
static void level_period(const LevelView& view, const PositionMap& map, const Band* band, bool period_bar, int& px,
                         int& py) {
    px = py = 0;
    if (!period_bar || !view.space.wraps || band || view.level < 1 || view.spacing <= 1) return;
    if (view.space.width % view.spacing == 0 && map.width > view.space.width / view.spacing)
        px = view.space.width / view.spacing;
    if (view.space.height % view.spacing == 0 && map.height > view.space.height / view.spacing)
        py = view.space.height / view.spacing;
}

void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options, Revisit* revisit,
                     const Band* band) {
    PixelStep step{view, map.positions.data(), map.width, options.coherence_bias, options.link_bias,
                   options.edge_guard};
    level_period(view, map, band, options.period_bar, step.period_x, step.period_y);
    step.seed = options.seed;
    correction_pass(options.threads, map.width, map.height, map.positions, step, revisit, band);
}

namespace {

// Finds the pixels whose 5x5 window lies inside one copy, which a
// correction with k = 1 leaves as they are. That is most of a level (83%
// of the finest level's pixels on stk_granite, in each of its two passes),
// and checking a window in its
// correction costs 25 gathered positions and a call per pixel. Here it is
// found for the whole map from the links between adjacent pixels, a few
// byte operations a pixel that vectorise: the window continues its centre
// at every tap if and only if each pixel continues its left neighbour along
// the window's rows (20 links) and its upper neighbour down the centre
// column (4), the differences of packed positions being additive (mod
// 2^32; exact inside the example, which the centre's reach guarantees).
// Skipped pixels keep the position a correction would have given them, so
// the bytes are the same; a later change in a window marks it due again
// (interleaved_pass).
void skip_inside_copies(const LevelView& v, const PositionMap& map, Revisit& revisit, const Band* band, int threads) {
    const int w = map.width, h = map.height;
    const int reach = kRadius * v.spacing;
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
            window_runs(row, w, kRadius, step_x, links.data(), runs.data() + std::size_t(i) * w);
            if (i + 1 < rows) window_down(row, row_at(y0 - kRadius + i + 1), w, step_y, down.data() + std::size_t(i) * w);
        }
        for (int y = y0; y < y1; ++y) {
            whole_windows(pos + std::size_t(y) * w, runs.data() + std::size_t(y - y0) * w,
                          down.data() + std::size_t(y - y0) * w, w, kRadius, uint32_t(reach), inside_x, inside_y,
                          whole.data());
            uint8_t* due = revisit.due.data() + std::size_t(y) * w;
            for (int x = 0; x < w; ++x) due[x] &= uint8_t(whole[std::size_t(x)] ^ 1);
        }
    });
}

}  // namespace

void skip_coherent(const LevelView& v, const PositionMap& map, Revisit& revisit, const Band* band, int threads,
                   bool period_bar) {
    const int w = map.width, h = map.height;
    const int reach = kRadius * v.spacing;
    if (v.k == 1 && w >= kSide && h >= kSide && v.space.width > 2 * reach && v.space.height > 2 * reach)
        skip_inside_copies(v, map, revisit, band, threads);
    // A pixel that repeats the example one period on is due whatever its
    // window: the correction has to move it.
    int px, py;
    level_period(v, map, band, period_bar, px, py);
    if (px == 0 && py == 0) return;
    const uint32_t* pos = map.positions.data();
    parallel_for(threads, std::size_t(h), 32, [&](std::size_t r0, std::size_t r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < w; ++x)
                if (repeats_period(pos, w, x, y, px, py, pos[std::size_t(y) * w + x]))
                    revisit.due[std::size_t(y) * w + x] = 1;
    });
}

}  // namespace vqtex::coherent
