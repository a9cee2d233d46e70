// constrained.cpp - hole filling and extrapolation by two-pass synthesis with
// symmetric neighbourhoods in spiral order (paper section 5.1). See
// constrained.hpp for the method.
#include "constrained.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "dsp/dsp.hpp"
#include "error.hpp"
#include "fill_order.hpp"
#include "matcher.hpp"
#include "parallel.hpp"
#include "pyramid.hpp"
#include "search_exhaustive.hpp"
#include "tsvq_search.hpp"
#include "tsvq_train.hpp"

namespace vqtex {
namespace {

// Which pixels of one pyramid level are known, with a summed-area table of
// the unknown ones so that "is this window wholly known" costs O(1).
struct KnownLevel {
    int width = 0, height = 0;
    std::vector<uint8_t> known;
    std::vector<uint32_t> unknown_sums;  // (width + 1) x (height + 1)

    bool is_known(int x, int y) const { return known[std::size_t(y) * std::size_t(width) + std::size_t(x)] != 0; }

    void build_sums() {
        const std::size_t w1 = std::size_t(width) + 1;
        unknown_sums.assign(w1 * (std::size_t(height) + 1), 0);
        for (int y = 0; y < height; ++y) {
            uint32_t row = 0;
            for (int x = 0; x < width; ++x) {
                row += is_known(x, y) ? 0u : 1u;
                unknown_sums[(std::size_t(y) + 1) * w1 + std::size_t(x) + 1] =
                    unknown_sums[std::size_t(y) * w1 + std::size_t(x) + 1] + row;
            }
        }
    }

    // [x0, x1] x [y0, y1] lies inside the level and holds no unknown pixel.
    bool rect_known(int x0, int y0, int x1, int y1) const {
        if (x0 < 0 || y0 < 0 || x1 >= width || y1 >= height) return false;
        const std::size_t w1 = std::size_t(width) + 1;
        const auto s = [&](int x, int y) { return unknown_sums[std::size_t(y) * w1 + std::size_t(x)]; };
        return s(x1 + 1, y1 + 1) - s(x0, y1 + 1) - s(x1 + 1, y0) + s(x0, y0) == 0;
    }

    std::size_t known_count() const { return std::size_t(std::count(known.begin(), known.end(), uint8_t(1))); }
};

std::vector<KnownLevel> known_pyramid(int width, int height, const std::vector<uint8_t>& known0,
                                      int levels) {
    std::vector<KnownLevel> out(static_cast<std::size_t>(levels));
    out[0].width = width;
    out[0].height = height;
    out[0].known = known0;
    out[0].build_sums();
    for (int l = 1; l < levels; ++l) {
        const KnownLevel& fine = out[std::size_t(l - 1)];
        KnownLevel& k = out[std::size_t(l)];
        k.width = pyramid_level_size(width, l);
        k.height = pyramid_level_size(height, l);
        k.known.assign(std::size_t(k.width) * std::size_t(k.height), 0);
        for (int y = 0; y < k.height; ++y)
            for (int x = 0; x < k.width; ++x) {
                bool all = true;
                for (int t = -2; t <= 2 && all; ++t)
                    for (int s = -2; s <= 2 && all; ++s)
                        all = fine.is_known(reflect_index(2 * x + s, fine.width),
                                            reflect_index(2 * y + t, fine.height));
                k.known[std::size_t(y) * std::size_t(k.width) + std::size_t(x)] = all ? 1 : 0;
            }
        k.build_sums();
    }
    return out;
}

// A rectangle a window reads at one depth, relative to the window's anchor
// (x >> depth, y >> depth).
struct Rect {
    int depth, x0, y0, x1, y1;
};

// The taps a query reads and the rectangles an example must have wholly
// known for the same window.
struct Window {
    std::vector<Tap> taps;
    std::vector<Rect> rects;
    std::size_t dimension(int channels) const { return taps.size() * std::size_t(channels); }
};

void add_coarser_rects(const Shape& shape, Window& w) {
    for (int d = 1; d < shape.levels; ++d) {
        const int r = coarser_window_size(shape, d) / 2;
        w.rects.push_back({d, -r, -r, r, r});
    }
}

// Pass 2: symmetric window at the level plus the coarser windows. The
// example's centre pixel must be known too, so its rectangle includes it.
Window symmetric_window(const Shape& shape) {
    Shape s = shape;
    s.causal = false;
    Window w;
    w.taps = shape_taps(s);
    const int ry = causal_reach_y(s), rx = causal_reach_x(s);
    w.rects.push_back({0, -rx, -ry, rx, ry});
    add_coarser_rects(s, w);
    return w;
}

// The single-pass reference: the causal window and the coarser ones.
Window causal_window(const Shape& shape) {
    Shape s = shape;
    s.causal = true;
    Window w;
    w.taps = shape_taps(s);
    const int ry = causal_reach_y(s), rx = causal_reach_x(s);
    if (ry > 0) w.rects.push_back({0, -rx, -ry, rx, -1});
    w.rects.push_back({0, -rx, 0, 0, 0});
    add_coarser_rects(s, w);
    return w;
}

// Pass 1: the coarser windows only, anchored at the even child (2X, 2Y);
// the 2x2 block of children must lie inside and be known.
Window block_window(const Shape& shape) {
    Window w;
    for (const Tap& t : shape_taps(shape))
        if (t.depth > 0) w.taps.push_back(t);
    w.rects.push_back({0, 0, 0, 1, 1});
    add_coarser_rects(shape, w);
    return w;
}

bool example_fits(const std::vector<KnownLevel>& known, int level, const Window& w, int x, int y) {
    for (const Rect& r : w.rects) {
        const KnownLevel& k = known[std::size_t(level + r.depth)];
        const int cx = x >> r.depth, cy = y >> r.depth;
        if (!k.rect_known(cx + r.x0, cy + r.y0, cx + r.x1, cy + r.y1)) return false;
    }
    return true;
}

// Gathers the window at (x, y), reflecting reads past the border.
void gather(const std::vector<Image>& pyramid, int level, const Window& w, int x, int y,
            uint8_t* out, std::size_t stride) {
    uint8_t* o = out;
    for (const Tap& t : w.taps) {
        const Image& img = pyramid[std::size_t(level + t.depth)];
        const uint8_t* p = img.at(reflect_index((x >> t.depth) + t.dx, img.width),
                                  reflect_index((y >> t.depth) + t.dy, img.height));
        for (int c = 0; c < img.channels; ++c) *o++ = p[c];
    }
    std::memset(o, 0, stride - std::size_t(o - out));
}

std::size_t count_examples(const std::vector<KnownLevel>& known, int level, const Window& w,
                           bool blocks) {
    const KnownLevel& k = known[std::size_t(level + (blocks ? 1 : 0))];
    std::size_t n = 0;
    for (int y = 0; y < k.height; ++y)
        for (int x = 0; x < k.width; ++x)
            n += example_fits(known, level, w, blocks ? 2 * x : x, blocks ? 2 * y : y) ? 1 : 0;
    return n;
}

// Every usable example neighbourhood of one level, in raster order. For
// pass-1 blocks, one entry per coarse position whose "pixel" is the 2x2
// block of children, (0,0) (1,0) (0,1) (1,1).
ExampleSet collect(const std::vector<Image>& pyramid, const std::vector<KnownLevel>& known,
                   int level, const Window& w, bool blocks) {
    const Image& img = pyramid[std::size_t(level)];
    const int c = img.channels;
    ExampleSet set;
    set.dimension = w.dimension(c);
    set.stride = dsp::padded_length(set.dimension);
    set.channels = blocks ? 4 * c : c;
    const KnownLevel& k = known[std::size_t(level + (blocks ? 1 : 0))];
    for (int y = 0; y < k.height; ++y)
        for (int x = 0; x < k.width; ++x) {
            const int ax = blocks ? 2 * x : x, ay = blocks ? 2 * y : y;
            if (!example_fits(known, level, w, ax, ay)) continue;
            const std::size_t i = set.positions.size();
            set.positions.push_back(uint32_t(y) * uint32_t(k.width) + uint32_t(x));
            set.vectors.resize((i + 1) * set.stride);
            gather(pyramid, level, w, ax, ay, set.vectors.data() + i * set.stride, set.stride);
            if (blocks) {
                for (int by = 0; by < 2; ++by)
                    for (int bx = 0; bx < 2; ++bx)
                        set.pixels.insert(set.pixels.end(), img.at(ax + bx, ay + by), img.at(ax + bx, ay + by) + c);
            } else {
                set.pixels.insert(set.pixels.end(), img.at(ax, ay), img.at(ax, ay) + c);
            }
        }
    return set;
}

std::shared_ptr<const Matcher> build_matcher(ExampleSet set, const FillOptions& o) {
    if (o.exhaustive) return std::make_shared<ExhaustiveMatcher>(std::move(set));
    TrainParams tp;
    const double fraction = std::clamp(o.codeword_fraction, 1e-6, 1.0);
    const std::size_t wanted = std::size_t(std::llround(double(set.count()) * fraction));
    tp.max_leaves = uint32_t(std::clamp<std::size_t>(wanted, std::min<std::size_t>(set.count(), 64), set.count()));
    // Medoid leaves: real example neighbourhoods with their real pixels (and
    // the only representative that works for pass-1 blocks).
    tp.representative = LeafRepresentative::Medoid;
    tp.entries_per_leaf = 1;
    tp.threads = o.threads;
    std::vector<uint32_t> all(set.count());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = uint32_t(i);
    auto book = std::make_shared<const Codebook>(train_codebook(set, all, tp));
    return std::make_shared<TsvqMatcher>(book, o.backtrack);
}

struct LevelPlan {
    Shape shape;              // pass-2 (symmetric) or causal shape
    Window main;              // pass-2 or causal window
    Window block;             // pass-1 window (two-pass, not the coarsest level)
    std::size_t examples = 0, blocks = 0;
};

struct Plan {
    int levels = 0;
    std::vector<LevelPlan> level;  // [0] = finest
    std::vector<KnownLevel> target_known, example_known;
};

// Why a pyramid of some depth cannot be used, for the error message.
struct Shortfall {
    std::string what;
};

bool try_plan(int levels, const FillOptions& o, int width, int height, const std::vector<uint8_t>& known0,
              const Image* example, Plan& plan, Shortfall& why) {
    plan = Plan{};
    plan.levels = levels;
    plan.target_known = known_pyramid(width, height, known0, levels);
    if (example)
        plan.example_known = known_pyramid(example->width, example->height,
                                           std::vector<uint8_t>(example->pixel_count(), 1), levels);
    const std::vector<KnownLevel>& ek = example ? plan.example_known : plan.target_known;
    const std::vector<Shape> shapes = default_shapes(levels);
    plan.level.resize(std::size_t(levels));
    for (int l = levels - 1; l >= 0; --l) {
        LevelPlan& lp = plan.level[std::size_t(l)];
        lp.shape = shapes[std::size_t(l)];
        lp.shape.levels = std::min(lp.shape.levels, levels - l);
        lp.shape.causal = o.method == FillMethod::Causal;
        lp.main = lp.shape.causal ? causal_window(lp.shape) : symmetric_window(lp.shape);
        const std::string where = " at pyramid level " + std::to_string(l) + " of " + std::to_string(levels);
        if (plan.target_known[std::size_t(l)].known_count() == 0) {
            why.what = "no pixel of the image stays known" + where;
            return false;
        }
        lp.examples = count_examples(ek, l, lp.main, false);
        if (lp.examples < kMinFillExamples) {
            why.what = "only " + std::to_string(lp.examples) + " example neighbourhoods " +
                       shape_to_string(lp.shape) + " lie wholly in known pixels" + where +
                       " (at least " + std::to_string(kMinFillExamples) + " are needed)";
            return false;
        }
        if (o.method == FillMethod::TwoPass && l + 1 < levels) {
            lp.block = block_window(lp.shape);
            lp.blocks = count_examples(ek, l, lp.block, true);
            if (lp.blocks < kMinFillExamples) {
                why.what = "only " + std::to_string(lp.blocks) + " coarse example windows lie wholly in known pixels" +
                           where + " (at least " + std::to_string(kMinFillExamples) + " are needed)";
                return false;
            }
        }
    }
    return true;
}

Plan make_plan(const FillOptions& o, const Image& image, const std::vector<uint8_t>& known0,
               const Image* example) {
    const Image& ex = example ? *example : image;
    if (o.levels < 0 || o.levels > kMaxLevels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "levels must be 0 (automatic) to " + std::to_string(kMaxLevels));
    const int deepest = o.levels ? o.levels
                                 : automatic_levels(std::min(ex.width, image.width), std::min(ex.height, image.height));
    Plan plan;
    Shortfall why;
    for (int levels = deepest; levels >= (o.levels ? o.levels : 1); --levels)
        if (try_plan(levels, o, image.width, image.height, known0, example, plan, why)) return plan;
    fail(VQTEX_ERROR_IMAGE_TOO_SMALL,
         "the mask leaves too little example: " + why.what +
             "; make the masked region smaller" + (o.levels ? std::string(", use fewer --levels") : std::string()) +
             (example ? std::string(" or give a larger example image") : std::string(" or give a separate example image (--example)")));
}

// Mean colour of the known pixels of a level: what hole pixels hold before
// they are synthesised at the coarsest level (only the single-pass reference
// can read them, through a mirrored border).
void fill_with_known_mean(Image& img, const KnownLevel& k) {
    const int c = img.channels;
    uint64_t sum[kMaxChannels] = {}, n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (k.is_known(x, y)) {
                for (int ch = 0; ch < c; ++ch) sum[ch] += img.at(x, y)[ch];
                ++n;
            }
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!k.is_known(x, y))
                for (int ch = 0; ch < c; ++ch) img.at(x, y)[ch] = uint8_t(n ? (sum[ch] + n / 2) / n : 128);
}

void fill_with_parent(Image& img, const Image& parent, const KnownLevel& k) {
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!k.is_known(x, y))
                std::memcpy(img.at(x, y), parent.at(x >> 1, y >> 1), std::size_t(img.channels));
}

// Stops the work when the caller's progress callback asks to (called only
// from the calling thread).
struct FillProgress {
    const ProgressFn* fn;
    uint64_t done = 0, total = 0;
    void advance(uint64_t n) {
        done += n;
        if (*fn && !(*fn)(done, total)) fail(VQTEX_ERROR_CANCELLED, "filling cancelled by the progress callback");
    }
};

constexpr std::size_t kProgressStep = 4096;
// Candidate pairs the coarsest level's masked search may compare before it
// falls back to a fixed subset of the examples (only reached with an
// explicit single-level pyramid on a large image).
constexpr uint64_t kMaskedSearchPairs = uint64_t(1) << 26;

// Coarsest level, first pass: spiral order, each pixel matched only on the
// taps of its symmetric window that are known or already filled.
void masked_spiral_fill(Image& img, std::vector<uint8_t>& valid, const std::vector<uint32_t>& order,
                        const ExampleSet& set, const Window& w, const std::vector<Image>& pyramid,
                        int level, const FillOptions& o, FillProgress& progress) {
    const int c = img.channels;
    std::vector<uint32_t> candidates(set.count());
    for (std::size_t i = 0; i < candidates.size(); ++i) candidates[i] = uint32_t(i);
    if (uint64_t(order.size()) * set.count() > kMaskedSearchPairs)
        candidates = choose_training_subset(set.count(), std::max<std::size_t>(kMinFillExamples, std::size_t(kMaskedSearchPairs / order.size())),
                                            o.seed ^ 0x6D61736Bull /* "mask" */);
    std::vector<uint8_t> query(set.stride);
    std::vector<uint16_t> offsets;
    std::vector<uint32_t> distance(candidates.size());
    std::size_t since = 0;
    for (const uint32_t index : order) {
        const int x = int(index % uint32_t(img.width)), y = int(index / uint32_t(img.width));
        gather(pyramid, level, w, x, y, query.data(), set.stride);
        offsets.clear();
        for (std::size_t t = 0; t < w.taps.size(); ++t) {
            const Tap& tap = w.taps[t];
            bool ok = true;
            if (tap.depth == 0) {
                const int px = reflect_index(x + tap.dx, img.width), py = reflect_index(y + tap.dy, img.height);
                ok = valid[std::size_t(py) * std::size_t(img.width) + std::size_t(px)] != 0;
            }
            if (ok)
                for (int ch = 0; ch < c; ++ch) offsets.push_back(uint16_t(t * std::size_t(c) + std::size_t(ch)));
        }
        uint32_t best = UINT32_MAX;
        std::size_t chosen = 0;
        for (std::size_t i = 0; i < candidates.size(); ++i) {
            const uint8_t* v = set.vector(candidates[i]);
            uint32_t d = 0;
            for (const uint16_t off : offsets) {
                const int diff = int(query[off]) - int(v[off]);
                d += uint32_t(diff * diff);
            }
            distance[i] = d;
            if (d < best) best = d, chosen = i;
        }
        if (o.tolerance) {
            const uint32_t threshold = tolerance_threshold(best, o.tolerance);
            const uint64_t salt = pixel_salt(o.seed, level, 0, x, y);
            uint64_t chosen_rank = candidate_rank(salt, candidates[chosen]);
            for (std::size_t i = 0; i < candidates.size(); ++i) {
                if (distance[i] > threshold) continue;
                const uint64_t rank = candidate_rank(salt, candidates[i]);
                if (rank < chosen_rank || (rank == chosen_rank && i < chosen)) chosen = i, chosen_rank = rank;
            }
        }
        std::memcpy(img.at(x, y), set.pixel(candidates[chosen]), std::size_t(c));
        valid[index] = 1;
        if (++since == kProgressStep) progress.advance(since), since = 0;
    }
    progress.advance(since);
}

// Pass 1 (not the coarsest level): every hole pixel from the coarser levels
// only. Reads nothing at this level, so pixels are independent: parallel.
void block_pass(Image& img, const std::vector<uint32_t>& order, const Matcher& matcher, const Window& w,
                const std::vector<Image>& pyramid, int level, const FillOptions& o, FillProgress& progress) {
    const std::size_t c = std::size_t(img.channels);
    constexpr std::size_t kBatch = 16384;
    for (std::size_t begin = 0; begin < order.size(); begin += kBatch) {
        const std::size_t end = std::min(order.size(), begin + kBatch);
        parallel_for(o.threads, end - begin, 1024, [&](std::size_t b, std::size_t e) {
            std::vector<uint8_t> query(matcher.stride());
            std::unique_ptr<MatchScratch> scratch = matcher.make_scratch();
            for (std::size_t i = begin + b; i < begin + e; ++i) {
                const int x = int(order[i] % uint32_t(img.width)), y = int(order[i] / uint32_t(img.width));
                gather(pyramid, level, w, x & ~1, y & ~1, query.data(), query.size());
                const MatchContext context{pixel_salt(o.seed, level, 1, x >> 1, y >> 1), o.tolerance};
                const uint8_t* block = matcher.match(query.data(), context, scratch.get());
                const std::size_t phase = std::size_t((y & 1) * 2 + (x & 1));
                std::memcpy(img.at(x, y), block + phase * c, c);
            }
        });
        progress.advance(end - begin);
    }
}

// Pass 2, or the single-pass reference: in `order`, each pixel from its full
// window as it stands (known, already re-synthesised, or predicted).
void ordered_pass(Image& img, const std::vector<uint32_t>& order, const Matcher& matcher, const Window& w,
                  const std::vector<Image>& pyramid, int level, int pass, const FillOptions& o,
                  FillProgress& progress) {
    std::vector<uint8_t> query(matcher.stride());
    std::unique_ptr<MatchScratch> scratch = matcher.make_scratch();
    std::size_t since = 0;
    for (const uint32_t index : order) {
        const int x = int(index % uint32_t(img.width)), y = int(index / uint32_t(img.width));
        gather(pyramid, level, w, x, y, query.data(), query.size());
        const MatchContext context{pixel_salt(o.seed, level, pass, x, y), o.tolerance};
        const uint8_t* pixel = matcher.match(query.data(), context, scratch.get());
        std::memcpy(img.at(x, y), pixel, std::size_t(img.channels));
        if (++since == kProgressStep) progress.advance(since), since = 0;
    }
    progress.advance(since);
}

}  // namespace

Image fill_region(const Image& image, const std::vector<uint8_t>& mask, const Image* example,
                  const FillOptions& o, FillReport* report) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (image.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "image to fill is empty");
    if (mask.size() != image.pixel_count())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "mask size does not match the image");
    if (example && example->channels != image.channels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "example image has " + std::to_string(example->channels) +
                                               " channels but the image has " + std::to_string(image.channels) +
                                               ": give an example with the same channels");
    std::vector<uint8_t> known0(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) known0[i] = mask[i] ? 0 : 1;
    if (std::find(known0.begin(), known0.end(), uint8_t(0)) == known0.end()) {
        if (report) *report = FillReport{};
        return image;  // nothing to fill
    }
    const Plan plan = make_plan(o, image, known0, example);
    const int levels = plan.levels;
    const std::vector<Image> example_pyramid =
        example ? build_pyramid(*example, levels, EdgeMode::Mirror) : std::vector<Image>{};
    std::vector<Image> pyramid = build_pyramid(image, levels, EdgeMode::Mirror);
    const std::vector<Image>& ex_pyr = example ? example_pyramid : pyramid;
    const std::vector<KnownLevel>& ex_known = example ? plan.example_known : plan.target_known;
    const bool two_pass = o.method == FillMethod::TwoPass;

    // Analysis: the example sets and their trees, two per level for the
    // two-pass method. The coarsest level's set is kept for the masked search.
    std::vector<std::shared_ptr<const Matcher>> main(static_cast<std::size_t>(levels)), blocks(static_cast<std::size_t>(levels));
    ExampleSet coarsest_set;
    const uint64_t trees = uint64_t(levels) + (two_pass ? uint64_t(levels - 1) : 0);
    uint64_t built = 0;
    const auto tree_done = [&] {
        ++built;
        if (o.analyse_progress && !o.analyse_progress(built, trees))
            fail(VQTEX_ERROR_CANCELLED, "filling cancelled by the progress callback");
    };
    for (int l = levels - 1; l >= 0; --l) {
        const LevelPlan& lp = plan.level[std::size_t(l)];
        ExampleSet set = collect(ex_pyr, ex_known, l, lp.main, false);
        if (two_pass && l == levels - 1) coarsest_set = set;
        main[std::size_t(l)] = build_matcher(std::move(set), o);
        tree_done();
        if (two_pass && l + 1 < levels) {
            blocks[std::size_t(l)] = build_matcher(collect(ex_pyr, ex_known, l, lp.block, true), o);
            tree_done();
        }
    }
    const auto t1 = Clock::now();

    // Synthesis, coarse to fine.
    std::vector<std::vector<uint8_t>> to_fill(static_cast<std::size_t>(levels));
    uint64_t total = 0;
    for (int l = 0; l < levels; ++l) {
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        to_fill[std::size_t(l)].resize(k.known.size());
        for (std::size_t i = 0; i < k.known.size(); ++i) to_fill[std::size_t(l)][i] = k.known[i] ? 0 : 1;
        const uint64_t n = uint64_t(k.known.size() - k.known_count());
        total += two_pass ? 2 * n : n;
    }
    FillProgress progress{&o.fill_progress, 0, total};
    FillReport r;
    r.levels = levels;
    for (int l = levels - 1; l >= 0; --l) {
        Image& img = pyramid[std::size_t(l)];
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        const LevelPlan& lp = plan.level[std::size_t(l)];
        const std::vector<uint8_t>& fill = to_fill[std::size_t(l)];
        if (l == levels - 1)
            fill_with_known_mean(img, k);
        else
            fill_with_parent(img, pyramid[std::size_t(l + 1)], k);
        if (two_pass) {
            const std::vector<uint32_t> order = spiral_order(img.width, img.height, fill);
            if (l == levels - 1) {
                std::vector<uint8_t> valid = k.known;
                masked_spiral_fill(img, valid, order, coarsest_set, lp.main, pyramid, l, o, progress);
            } else {
                block_pass(img, order, *blocks[std::size_t(l)], lp.block, pyramid, l, o, progress);
            }
            ordered_pass(img, order, *main[std::size_t(l)], lp.main, pyramid, l, 2, o, progress);
        } else {
            ordered_pass(img, raster_order(img.width, img.height, fill), *main[std::size_t(l)], lp.main,
                         pyramid, l, 0, o, progress);
        }
    }
    const auto t2 = Clock::now();
    if (report) {
        r.shapes.resize(std::size_t(levels));
        r.examples.resize(std::size_t(levels));
        r.block_examples.resize(std::size_t(levels));
        r.filled.resize(std::size_t(levels));
        for (int l = 0; l < levels; ++l) {
            const LevelPlan& lp = plan.level[std::size_t(l)];
            r.shapes[std::size_t(l)] = lp.shape;
            r.examples[std::size_t(l)] = lp.examples;
            r.block_examples[std::size_t(l)] = lp.blocks;
            const KnownLevel& k = plan.target_known[std::size_t(l)];
            r.filled[std::size_t(l)] = k.known.size() - k.known_count();
        }
        r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
        r.fill_seconds = std::chrono::duration<double>(t2 - t1).count();
        *report = r;
    }
    // Level 0 differs from the input only under the mask: copy just those.
    Image out = image;
    const Image& filled = pyramid[0];
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (mask[i])
            std::memcpy(out.pixels.data() + i * std::size_t(image.channels),
                        filled.pixels.data() + i * std::size_t(image.channels), std::size_t(image.channels));
    return out;
}

}  // namespace vqtex
