// atlas_choice.hpp - what an atlas file stores (docs/ATLAS.md
// "Which atlas"): the part of the example that becomes the atlas and the
// AV1 quality it is coded at, for a byte budget. The codeword count, the
// paper's rate knob (section 6), is the atlas's area; the quality preset
// names a budget per example pixel, and the finest AV1 level that fits it
// is taken.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.hpp"
#include "metrics.hpp"

namespace vqtex {

// Whether an atlas wraps, and whether it is decoded with the period bar
// (CoherentOptions::period_bar; only an atlas that wraps is).
struct AtlasWrap {
    bool wraps = false;
    bool period_bar = false;
};

struct AtlasChoiceOptions {
    uint64_t budget = 0;            // bytes the whole file may take; 0: the quality's
    int quality = 50;               // the preset whose budget applies when budget is 0
    int levels = 0;                 // the engine's stack depth; 0 = the deepest the atlas allows
    bool example_tileable = false;  // the example wraps
    // Otherwise an atlas that is the whole example wraps when the example
    // repeats its tile (example_wrap.hpp).
    bool detect_tileable = false;
    uint64_t seed = 1;              // the file's default decoding seed
    int threads = 1;                // the file does not depend on it
    // false: the rule before large examples and periods, the whole example
    // or its largest top-left crop that fits (what vqtex-bench's compact
    // protocol compares with).
    bool compaction = true;
    // How the output of a wrapping atlas is laid out: chosen by the proxy
    // (auto), or always one way.
    enum class Layout { Auto, Coherent, Quilt };
    Layout layout = Layout::Auto;
};

struct AtlasChoice {
    std::vector<uint8_t> file;  // a whole atlas file (format 5)
    int cq = 0;                 // libaom's level, 0..63
    int levels = 0;
    Image atlas;                // what was coded (before coding)
    uint32_t attempts = 0;      // AV1 encodes tried
    int x = 0, y = 0;           // where the atlas lies in the example
    bool tile = false;          // the atlas is the tile the example repeats
    bool wraps = false;         // the atlas wraps (the file's example_tileable)
    bool period_bar = false;    // decoded with the period bar (format 15)
    bool quilt = false;         // laid out by quilting (format 21)
    bool example_tiles = false; // the example's wrap is seamless (example_wrap.hpp)
};

// The finest AV1 level, 0..63, at which `size_at(level)` (a file's bytes)
// fits `budget`, or -1 when even 63 does not. Sizes fall as the level
// rises, so the search bisects: about 7 encodes.
template <typename SizeAt>
int finest_fitting_level(uint64_t budget, SizeAt&& size_at) {
    if (size_at(63) > budget) return -1;
    int lo = 0, hi = 62, best = 63;  // the answer lies in [lo, hi + 1]
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (size_at(mid) <= budget) {
            best = mid;
            hi = mid - 1;
        } else {
            lo = mid + 1;
        }
    }
    return best;
}

// The finest fitting level found near `guess`, a level that fitted at a
// faster libaom speed (whose sizes are within a few percent of a finer
// speed's): a few encodes instead of a bisection's seven. -1 when even 63
// does not fit.
template <typename SizeAt>
int finest_fitting_near(uint64_t budget, int guess, SizeAt&& size_at) {
    auto fits = [&](int cq) { return uint64_t(size_at(cq)) <= budget; };
    int cq = guess < 0 ? 63 : std::min(guess, 63);
    if (!fits(cq)) {
        while (cq < 63 && !fits(cq)) ++cq;
        return fits(cq) ? cq : -1;
    }
    while (cq > 0 && fits(cq - 1)) --cq;
    return cq;
}

// The byte budget of a quality preset for an example of `pixels` pixels:
// 1000 bytes per 128x128 at quality 0, doubling every 25 points (4 KB at
// the default 50, 16 KB at 100), and never under 512 bytes, so that a tiny
// example still gets an atlas worth decoding.
uint64_t atlas_budget_of_quality(int quality, uint64_t pixels);

// The most example pixels a quality's budget pays for: a larger example
// gets the budget of a 256x256 one (16 KB at the default), since a
// stationary texture's variety does not grow with the photograph's area
// (docs/ATLAS.md "Large examples").
inline constexpr uint64_t kBudgetedPixels = 256 * 256;

// Examples above this many pixels (after their period, if they repeat)
// take the large examples' path: parts of them compete at the budget.
inline constexpr uint64_t kLargeExamplePixels = 2 * 256 * 256;

// An example above kBudgetedPixels that repeats is first reduced to its
// tile (example_period.hpp), which wraps when it repeats both ways. Budgets from a quality count at most kBudgetedPixels.
// Examples above kLargeExamplePixels: square parts of the tile or example,
// of sides set by the budget (about 4, 2 and 1 KB per 128x128), each where
// its colours' mean and spread are closest to the whole's, compete as the
// crops below do, libaom's level searched at a fast speed and set at a
// finer one (docs/ATLAS.md "Large examples"). Otherwise:
// the finest AV1 level of the whole example whose file fits the budget.
// At budgets of at most 0.13 bytes per example pixel, crops of 3/4 and 1/2
// of the side (top-left and centre), each at its finest fitting level,
// compete with it: each file is decoded and its texture scored against the
// example with metrics/ (docs/ATLAS.md "Which atlas" gives the rule). When
// even the coarsest level of the whole example does not fit, the largest
// top-left crop (12/16, 9/16... of each side) that fits. Throws
// LIMIT_EXCEEDED when nothing fits. The bytes do not depend on the thread
// count (libaom runs on one thread; the metrics are seeded).
AtlasChoice choose_atlas(const Image& example, const AtlasChoiceOptions& options);

// On a wrapping atlas that is the whole example (not a repeated tile), the
// coherent engine and quilting (engine/quilt.hpp) compete: each decodes
// the chosen file at twice the atlas's side (at most 512), seeds 2 and 3,
// and quilting is kept when its coherence and its coherence at half
// resolution (means) are both at least kQuiltGain below the engine's and
// its SWD no more than kQuiltSwdSlack above. Cells, stones and planks then
// meet where they agree instead of along the coarse levels' lines; on
// stochastic textures, where quilting repeats its blocks and leaves more
// of the example out, the engine stays. On the 13 examples that tile that
// a judge compared blind, the rule picks the judge's choice on all 13
// (docs/ATLAS.md "Examples that tile"; the margin is thin on the demo's
// cells).
inline constexpr double kQuiltGain = 0.05;
inline constexpr double kQuiltSwdSlack = 0.15;
inline constexpr int kQuiltProxySeeds = 2;

// An image as the metrics library takes it (a copy), for the proxies
// that score candidate files.
vqtex_metrics::Image as_metrics_image(const Image& img);

// Where an s x s part of `source` looks most like the whole: of nine
// places (corners, edge middles, centre), the one whose colours' mean and
// spread are nearest the whole's. On a stationary texture any place would
// do; on a lit or graded one this keeps the middle of its range.
std::array<int, 2> representative_place(const Image& source, int s);

// libaom's speeds on the large path: sizes at the fast one are within a
// few percent of the fine one's at the same level, at a tenth of the time,
// so the bisection runs fast and a few fine encodes settle the level
// (docs/ATLAS.md "Large examples" has the measurements).
inline constexpr int kSearchSpeed = 8;
inline constexpr int kFinalSpeed = 6;

// The proxy's output side on the large path: enough for the example's
// windows to recur, far less than the example; and the windows its nearest
// neighbours are sought among (every second or fourth of a large
// example's), which keeps each index near 10 MB.
inline constexpr int kLargeProxySide = 512;
inline constexpr int kLargeProxyWindows = 65536;
// The proxies' metrics hold copies of the example at several scales: up
// to this many example pixels they run on the threads, above it one at a
// time (each decode on the threads), which keeps the encoder within four
// times the example plus 64 MB.
inline constexpr std::size_t kProxiesTogetherPixels = 1024 * 1024;

// The sides of the square parts a large example's budget pays for: about
// 4, 2 and 1 KB per 128x128 of part, multiples of 8, at most `limit`
// (distinct, smallest first).
std::vector<int> large_part_sides(uint64_t budget, int limit);

// What the encoder can measure of a candidate file: the texture it decodes
// to, against the example.
struct ProxyScores {
    double completeness = 0, swd = 0, coherence = 0;
};
ProxyScores proxy_scores_of(const vqtex_metrics::Image& reference, const vqtex_metrics::Image& texture,
                            int max_windows);

// Throws LIMIT_EXCEEDED: no `what` ("atlas", "atlas of the 3 maps") fits
// the budget, with what to do about it.
[[noreturn]] void fail_nothing_fits(const std::string& what, uint64_t budget);

// The candidate whose scores, each relative to the least any candidate has
// (per map, for a set: scores[candidate][map]), add up to the least; an
// empty entry is a candidate that did not fit. -1 when none fitted.
int best_relative(const std::vector<std::vector<ProxyScores>>& scores);

}  // namespace vqtex
