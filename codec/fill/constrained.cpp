// constrained.cpp - hole filling and extrapolation by two-pass synthesis with
// symmetric neighbourhoods in spiral order (paper section 5.1). See
// constrained.hpp for the method.
#include "fill/constrained.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "dsp/dsp.hpp"
#include "common/error.hpp"
#include "fill/fill_order.hpp"
#include "engine/coherent_candidates.hpp"
#include "engine/matcher.hpp"
#include "common/parallel.hpp"
#include "engine/pyramid.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "tsvq/tsvq_search.hpp"
#include "tsvq/tsvq_train.hpp"

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

// Context pyramid of the target: which pixels of each coarser level are
// usable as context, and with which values. A coarser pixel is usable when
// at least `threshold`/256 of its filter weight falls on usable finer pixels;
// its value is then the filter over those pixels alone, renormalised
// (normalised convolution). With the strict rule of known_pyramid, which
// wants the whole footprint, holes grow by about two pixels per level, and
// the ring they grow by is synthesised at the coarse level although the
// finer level knows most of it: the coarse context of the finer level's
// boundary pixels then disagrees with their known neighbours and the fill
// meets them with a step (a visible seam). A wholly known footprint gives
// exactly the pyramid's value, so strict pixels are unchanged.
std::vector<KnownLevel> context_known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels,
                                              int threshold) {
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
                int weight = 0;
                for (int t = 0; t < 5; ++t)
                    for (int s = 0; s < 5; ++s)
                        if (fine.is_known(reflect_index(2 * x + s - 2, fine.width), reflect_index(2 * y + t - 2, fine.height)))
                            weight += kPyramidTaps[t] * kPyramidTaps[s];
                k.known[std::size_t(y) * std::size_t(k.width) + std::size_t(x)] = weight >= threshold ? 1 : 0;
            }
        k.build_sums();
    }
    return out;
}

// Known pixels for example windows: a coarser pixel counts only when its
// whole filter footprint is known (all 256/256 of the weight).
std::vector<KnownLevel> known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels) {
    return context_known_pyramid(width, height, known0, levels, 256);
}

// The values of context_known_pyramid: every usable pixel of each coarser
// level recomputed from the usable pixels of the level below (exact integer
// arithmetic; a wholly known footprint gives the pyramid's own value).
void apply_context_values(std::vector<Image>& pyramid, const std::vector<KnownLevel>& known) {
    for (std::size_t l = 1; l < pyramid.size(); ++l) {
        const Image& fine = pyramid[l - 1];
        const KnownLevel& fk = known[l - 1];
        Image& img = pyramid[l];
        const int c = img.channels;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                if (!known[l].is_known(x, y)) continue;
                uint32_t sum[kMaxChannels] = {}, weight = 0;
                for (int t = 0; t < 5; ++t)
                    for (int s = 0; s < 5; ++s) {
                        const int fx = reflect_index(2 * x + s - 2, fine.width), fy = reflect_index(2 * y + t - 2, fine.height);
                        if (!fk.is_known(fx, fy)) continue;
                        const uint32_t w = uint32_t(kPyramidTaps[t] * kPyramidTaps[s]);
                        weight += w;
                        for (int ch = 0; ch < c; ++ch) sum[ch] += w * fine.at(fx, fy)[ch];
                    }
                for (int ch = 0; ch < c; ++ch) img.at(x, y)[ch] = uint8_t((sum[ch] + weight / 2) / weight);
            }
    }
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
        const int r = coarser_extent(std::max(shape.rows, shape.cols), d) / 2;
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

// One level's example neighbourhoods (pass-2 windows or pass-1 blocks) with
// the tree over them, and a map from example position to neighbourhood, so
// that the position a pixel was copied from can be turned back into
// candidates for its neighbours (coherence, see coherent_choice).
class ExampleIndex {
public:
    // `width` x `height`: the grid the set's positions index (the example
    // level, or the level above it for blocks).
    ExampleIndex(ExampleSet set, int width, int height, const FillOptions& o)
        : set_(std::move(set)), width_(width), height_(height), backtrack_(o.backtrack) {
        at_.assign(std::size_t(width) * std::size_t(height), -1);
        for (std::size_t i = 0; i < set_.count(); ++i) at_[set_.positions[i]] = int32_t(i);
        if (o.exhaustive) {
            exhaustive_ = std::make_unique<ExhaustiveMatcher>(set_);
            return;
        }
        TrainParams tp;
        std::vector<uint32_t> subset(set_.count());
        for (std::size_t i = 0; i < subset.size(); ++i) subset[i] = uint32_t(i);
        if (o.max_train && subset.size() > o.max_train)
            subset = choose_training_subset(set_.count(), o.max_train, o.seed ^ 0x7472616Eull /* "tran" */);
        const double fraction = std::clamp(o.codeword_fraction, 1e-6, 1.0);
        const std::size_t wanted = std::size_t(std::llround(double(subset.size()) * fraction));
        tp.max_leaves = uint32_t(std::clamp<std::size_t>(wanted, std::min<std::size_t>(subset.size(), 64), subset.size()));
        // Medoid leaves: real example neighbourhoods, whose tie key is their
        // index in the set, so a leaf names a position in the example.
        tp.representative = LeafRepresentative::Medoid;
        tp.entries_per_leaf = 1;
        tp.threads = o.threads;
        tsvq_ = std::make_unique<TsvqMatcher>(std::make_shared<const Codebook>(train_codebook(set_, subset, tp)),
                                              o.backtrack);
    }

    const ExampleSet& set() const { return set_; }
    int width() const { return width_; }
    std::unique_ptr<MatchScratch> make_scratch() const {
        return tsvq_ ? tsvq_->make_scratch() : nullptr;
    }
    // The neighbourhood the tree (or the exhaustive search) finds.
    uint32_t search(const uint8_t* query, const MatchContext& context, MatchScratch* scratch) const {
        if (exhaustive_) return uint32_t(exhaustive_->nearest(query, context));
        const std::size_t leaf = tsvq_->search(query, backtrack_, scratch, context);
        return tsvq_->codebook().leaf_key(leaf);
    }
    // The neighbourhood at example position (x, y), or -1 when there is none
    // (outside, or its window is not wholly known).
    int32_t at(int x, int y) const {
        if (x < 0 || y < 0 || x >= width_ || y >= height_) return -1;
        return at_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
    }

private:
    ExampleSet set_;
    int width_, height_;
    uint32_t backtrack_;
    std::vector<int32_t> at_;
    std::unique_ptr<TsvqMatcher> tsvq_;
    std::unique_ptr<ExhaustiveMatcher> exhaustive_;
};

// Coherence (after Ashikhmin 2001, as a candidate set beside the tree's
// answer): a pixel whose neighbour at offset d was copied from example
// position s is offered the example neighbourhood at s - d, which continues
// the neighbour's patch. The tree's answer and the coherent candidates are
// compared on the same query with exact distances; a coherent candidate wins
// when it is within the bias of the tree's (bias in 1/256: 0 = only when at
// least as close). Ties go to the lower index, so the choice is a pure
// function of the query and the neighbours' sources.
// The list is the one the coherent engine uses (engine/coherent_candidates.hpp);
// here its values are neighbourhood indices, every one a continuation.
struct Candidates {
    CandidateList<32> list;
    void add(int32_t i) {
        if (i >= 0) list.add(uint32_t(i), true);
    }
};

uint32_t coherent_choice(const ExampleSet& set, const uint8_t* query, uint32_t found, const Candidates& c,
                         uint32_t bias) {
    const dsp::Kernels& k = dsp::kernels();
    if (c.list.size() == 0) return found;
    const uint32_t found_distance = k.ssd(query, set.vector(found), set.stride);
    uint32_t best = UINT32_MAX, chosen = UINT32_MAX;
    for (int i = 0; i < c.list.size(); ++i) {
        const uint32_t index = c.list[i];
        const uint32_t d = k.ssd(query, set.vector(index), set.stride);
        if (d < best || (d == best && index < chosen)) best = d, chosen = index;
    }
    return uint64_t(best) * 256 <= uint64_t(found_distance) * (256 + bias) ? chosen : found;
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
    plan.target_known = o.method == FillMethod::TwoPass && o.context_threshold > 0 ? context_known_pyramid(width, height, known0, levels, o.context_threshold)
                                                : known_pyramid(width, height, known0, levels);
    plan.example_known = example ? known_pyramid(example->width, example->height,
                                                 std::vector<uint8_t>(example->pixel_count(), 1), levels)
                                 : known_pyramid(width, height, known0, levels);
    const std::vector<KnownLevel>& ek = plan.example_known;
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

// Where each pixel of a target level was copied from: an example position
// (y * example width + x at the same level), or -1 (known pixels, and pixels
// not synthesised yet).
struct SourceMap {
    int width = 0, height = 0;
    std::vector<int32_t> at;
    SourceMap(int w, int h) : width(w), height(h), at(std::size_t(w) * std::size_t(h), -1) {}
    int32_t get(int x, int y) const {
        if (x < 0 || y < 0 || x >= width || y >= height) return -1;
        return at[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

// The coherent candidates of pixel (x, y): for each neighbour within
// `radius` with a source s, the neighbourhood at s - offset.
void add_coherent(Candidates& c, const SourceMap& src, const ExampleIndex& ex, int x, int y, int radius,
                  bool include_self) {
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            if (!include_self && dx == 0 && dy == 0) continue;
            const int32_t s = src.get(x + dx, y + dy);
            if (s < 0) continue;
            const ShiftedSource u = shifted_source(int(s) % ex.width(), int(s) / ex.width(), dx, dy, 1);
            c.add(ex.at(u.x, u.y));
        }
}

// Coarsest level, first pass: spiral order, each pixel matched only on the
// taps of its symmetric window that are known or already filled.
void masked_spiral_fill(Image& img, std::vector<uint8_t>& valid, SourceMap& src, const std::vector<uint32_t>& order,
                        const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid,
                        int level, const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    const int c = img.channels;
    std::vector<uint32_t> candidates(set.count());
    for (std::size_t i = 0; i < candidates.size(); ++i) candidates[i] = uint32_t(i);
    const bool all = uint64_t(order.size()) * set.count() <= kMaskedSearchPairs;
    if (!all)
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
            // The candidates are in ascending order (all, or a sorted
            // subset), so the lowest key is also the lowest index.
            NearTieChoice choice(pixel_salt(o.seed, level, 0, x, y), candidates[chosen]);
            for (std::size_t i = 0; i < candidates.size(); ++i)
                if (distance[i] <= threshold && choice.offer(candidates[i])) chosen = i;
        }
        if (all && o.coherence) {
            // Every example is a candidate here, so the coherent ones'
            // masked distances are already known.
            Candidates coherent;
            add_coherent(coherent, src, ex, x, y, o.coherence_radius, false);
            uint32_t cbest = UINT32_MAX, cchosen = UINT32_MAX;
            for (int k = 0; k < coherent.list.size(); ++k) {
                const uint32_t i = coherent.list[k];
                if (distance[i] < cbest || (distance[i] == cbest && i < cchosen)) cbest = distance[i], cchosen = i;
            }
            if (cchosen != UINT32_MAX &&
                uint64_t(cbest) * 256 <= uint64_t(distance[chosen]) * (256 + o.coherence_bias))
                chosen = cchosen;
        }
        std::memcpy(img.at(x, y), set.pixel(candidates[chosen]), std::size_t(c));
        src.at[index] = int32_t(set.positions[candidates[chosen]]);
        valid[index] = 1;
        if (++since == kProgressStep) progress.advance(since), since = 0;
    }
    progress.advance(since);
}

// Pass 1 (not the coarsest level): every hole pixel from the coarser levels
// only. Reads nothing at this level, so pixels are independent: parallel.
// Coherent candidates come from the parent level's sources: the block under
// the parent's own source continues its patch one level finer.
void block_pass(Image& img, SourceMap& src, const SourceMap& parent_src, const std::vector<uint32_t>& order,
                const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid, int level,
                int example_width, const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    const std::size_t c = std::size_t(img.channels);
    constexpr std::size_t kBatch = 16384;
    for (std::size_t begin = 0; begin < order.size(); begin += kBatch) {
        const std::size_t end = std::min(order.size(), begin + kBatch);
        parallel_for(o.threads, end - begin, 1024, [&](std::size_t b, std::size_t e) {
            std::vector<uint8_t> query(set.stride);
            std::unique_ptr<MatchScratch> scratch = ex.make_scratch();
            for (std::size_t i = begin + b; i < begin + e; ++i) {
                const int x = int(order[i] % uint32_t(img.width)), y = int(order[i] / uint32_t(img.width));
                gather(pyramid, level, w, x & ~1, y & ~1, query.data(), query.size());
                const MatchContext context{pixel_salt(o.seed, level, 1, x >> 1, y >> 1), o.tolerance};
                uint32_t chosen = ex.search(query.data(), context, scratch.get());
                if (o.coherence) {
                    Candidates coherent;
                    add_coherent(coherent, parent_src, ex, x >> 1, y >> 1, 1, true);
                    chosen = coherent_choice(set, query.data(), chosen, coherent, o.coherence_bias);
                }
                const int phase_x = x & 1, phase_y = y & 1;
                std::memcpy(img.at(x, y), set.pixel(chosen) + std::size_t(phase_y * 2 + phase_x) * c, c);
                const uint32_t coarse = set.positions[chosen];
                const int sx = 2 * int(coarse % uint32_t(ex.width())) + phase_x;
                const int sy = 2 * int(coarse / uint32_t(ex.width())) + phase_y;
                src.at[order[i]] = sy * example_width + sx;
            }
        });
        progress.advance(end - begin);
    }
}

// Pass 2, its refinement sweeps, or the single-pass reference: in `order`,
// each pixel from its full window as it stands (known, already
// re-synthesised, or predicted).
void ordered_pass(Image& img, SourceMap& src, const std::vector<uint32_t>& order, const ExampleIndex& ex,
                  const Window& w, const std::vector<Image>& pyramid, int level, int pass, bool coherence,
                  const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    std::vector<uint8_t> query(set.stride);
    std::unique_ptr<MatchScratch> scratch = ex.make_scratch();
    std::size_t since = 0;
    for (const uint32_t index : order) {
        const int x = int(index % uint32_t(img.width)), y = int(index / uint32_t(img.width));
        gather(pyramid, level, w, x, y, query.data(), query.size());
        const MatchContext context{pixel_salt(o.seed, level, pass, x, y), o.tolerance};
        uint32_t chosen = ex.search(query.data(), context, scratch.get());
        if (coherence) {
            Candidates coherent;
            add_coherent(coherent, src, ex, x, y, o.coherence_radius, false);
            chosen = coherent_choice(set, query.data(), chosen, coherent, o.coherence_bias);
        }
        std::memcpy(img.at(x, y), set.pixel(chosen), std::size_t(img.channels));
        src.at[index] = int32_t(set.positions[chosen]);
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
    const std::vector<KnownLevel>& ex_known = plan.example_known;
    if (o.method == FillMethod::TwoPass && o.context_threshold > 0) apply_context_values(pyramid, plan.target_known);
    const bool two_pass = o.method == FillMethod::TwoPass;

    // Analysis: the example sets and their trees, two per level for the
    // two-pass method.
    std::vector<std::unique_ptr<ExampleIndex>> main(static_cast<std::size_t>(levels)), blocks(static_cast<std::size_t>(levels));
    const uint64_t trees = uint64_t(levels) + (two_pass ? uint64_t(levels - 1) : 0);
    uint64_t built = 0;
    const auto tree_done = [&] {
        ++built;
        if (o.analyse_progress && !o.analyse_progress(built, trees))
            fail(VQTEX_ERROR_CANCELLED, "filling cancelled by the progress callback");
    };
    for (int l = levels - 1; l >= 0; --l) {
        const LevelPlan& lp = plan.level[std::size_t(l)];
        const KnownLevel& ek = ex_known[std::size_t(l)];
        main[std::size_t(l)] = std::make_unique<ExampleIndex>(collect(ex_pyr, ex_known, l, lp.main, false), ek.width,
                                                              ek.height, o);
        tree_done();
        if (two_pass && l + 1 < levels) {
            const KnownLevel& ec = ex_known[std::size_t(l + 1)];
            blocks[std::size_t(l)] = std::make_unique<ExampleIndex>(collect(ex_pyr, ex_known, l, lp.block, true),
                                                                    ec.width, ec.height, o);
            tree_done();
        }
    }
    const auto t1 = Clock::now();

    // Synthesis, coarse to fine.
    std::vector<std::vector<uint8_t>> to_fill(static_cast<std::size_t>(levels));
    uint64_t total = 0;
    const uint64_t passes = two_pass ? 2 + uint64_t(std::max(o.sweeps, 0)) : 1;
    for (int l = 0; l < levels; ++l) {
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        to_fill[std::size_t(l)].resize(k.known.size());
        for (std::size_t i = 0; i < k.known.size(); ++i) to_fill[std::size_t(l)][i] = k.known[i] ? 0 : 1;
        total += passes * uint64_t(k.known.size() - k.known_count());
    }
    FillProgress progress{&o.fill_progress, 0, total};
    FillReport r;
    r.levels = levels;
    std::vector<SourceMap> sources;
    for (int l = 0; l < levels; ++l) sources.emplace_back(pyramid[std::size_t(l)].width, pyramid[std::size_t(l)].height);
    for (int l = levels - 1; l >= 0; --l) {
        Image& img = pyramid[std::size_t(l)];
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        const LevelPlan& lp = plan.level[std::size_t(l)];
        const ExampleIndex& ex = *main[std::size_t(l)];
        SourceMap& src = sources[std::size_t(l)];
        const std::vector<uint8_t>& fill = to_fill[std::size_t(l)];
        if (l == levels - 1)
            fill_with_known_mean(img, k);
        else
            fill_with_parent(img, pyramid[std::size_t(l + 1)], k);
        if (two_pass) {
            const std::vector<uint32_t> order = spiral_order(img.width, img.height, fill);
            if (l == levels - 1) {
                std::vector<uint8_t> valid = k.known;
                masked_spiral_fill(img, valid, src, order, ex, lp.main, pyramid, l, o, progress);
            } else {
                block_pass(img, src, sources[std::size_t(l + 1)], order, *blocks[std::size_t(l)], lp.block, pyramid,
                           l, ex_known[std::size_t(l)].width, o, progress);
            }
            ordered_pass(img, src, order, ex, lp.main, pyramid, l, 2, o.coherence, o, progress);
            // Refinement sweeps: back from the centre to the border, then
            // out again; each pixel now sees final values on every side.
            const std::vector<uint32_t> reverse(order.rbegin(), order.rend());
            for (int s = 0; s < o.sweeps; ++s)
                ordered_pass(img, src, s % 2 == 0 ? reverse : order, ex, lp.main, pyramid, l, 3 + s, o.coherence, o,
                             progress);
        } else {
            ordered_pass(img, src, raster_order(img.width, img.height, fill), ex, lp.main, pyramid, l, 0, false, o,
                         progress);
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
