// paper_levels.hpp - the level driver of the paper engine (Wei & Levoy 2000,
// sections 2.2-2.5 for stills, 5.2 for animations), written once over the
// dimension: an output pyramid is synthesised coarsest level first, each
// level initialised (matched noise, or the coarser level upsampled), then
// scanned frame by frame (a still is one frame) in the rotated raster order
// of wavefront.hpp, each frame closed at its seam and each level at its
// temporal wrap where the model asks for it.
//
// A level of either dimension is a stack of frames: an Image is one frame,
// a Volume keeps its frames stacked in one Image (volume.hpp). The driver
// does everything that depends only on that stack; the dimension supplies
// the per-level work through a type Dim with
//   Dim::Grid                          Image or Volume
//   Dim::stack(grid), Dim::frame_height(grid), Dim::frames(grid)
//   dim.levels(), dim.make_level(l), dim.histogram(l)
//   Dim::Level(dim, l, pyramid)        one level's scan, built after the
//                                      level is initialised, with
//     shape()                          the causal shape the scan runs with
//     stride(), make_scratch()         one worker's query and search memory
//     begin_frame(t)                   before frame t's scan
//     visit(x, y, t, query, scratch)   synthesise one pixel
//     close_frame(t, threads)          after frame t's scan (seam closing)
//     close_level(threads)             after the level's last frame
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/image.hpp"
#include "engine/matcher.hpp"
#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"
#include "engine/synthesis.hpp"
#include "engine/wavefront.hpp"

namespace vqtex {

// Pixel replication: each pixel of frame t takes its parent's value, the
// ancestor (x >> 1, y >> 1, t >> 1) the neighbourhoods use. Both images are
// frame stacks (frames of `height` and `parent_height` rows).
inline void upsample_parent(const Image& parent, int parent_height, Image& stack, int height) {
    for (int row = 0; row < stack.height; ++row) {
        const int t = row / height, y = row - t * height;
        const int parent_row = (t >> 1) * parent_height + (y >> 1);
        for (int x = 0; x < stack.width; ++x)
            copy_pixel(stack.at(x, row), parent.at(x >> 1, parent_row), stack.channels);
    }
}

// The check every level's matchers pass before the scan.
inline void require_stride(std::size_t layout_stride, const Matcher* matcher, const char* what, int level) {
    if (!matcher || layout_stride != matcher->stride())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(what) + " disagree at level " + std::to_string(level));
}

// What the driver needs of the caller besides the dimension.
struct PaperRun {
    LevelInit init = LevelInit::Parent;
    uint64_t seed = 0;
    int threads = 1;
    const ProgressFn* progress = nullptr;
    // Progress is reported by the calling thread after each of its rows
    // (true) or after each frame (false).
    bool progress_per_row = false;
    // For tests: per level, the order of the causal scan's visits,
    // indexed (t * height + y) * width + x. Forces one thread.
    std::vector<std::vector<uint32_t>>* trace = nullptr;
};

// The common run settings of both dimensions' options.
template <typename Options>
PaperRun paper_run(const Options& options) {
    PaperRun run;
    run.init = options.init;
    run.seed = options.seed;
    run.threads = options.threads;
    run.progress = &options.progress;
    return run;
}

// What every dimension reads of its model and options: the levels and their
// histograms.
template <typename Model, typename Options>
class PaperDimension {
public:
    PaperDimension(const Model& model, const Options& options) : model_(model), options_(options) {}
    int levels() const { return int(model_.levels.size()); }
    const LevelHistogram& histogram(int l) const { return model_.levels[std::size_t(l)].histogram; }
    const Model& model() const { return model_; }
    const Options& options() const { return options_; }

private:
    const Model& model_;
    const Options& options_;
};

// What every dimension's level holds: its models, the run's options, the
// pyramid and the causal layout the scan gathers with (checked against the
// level's matcher).
template <typename LevelModelT, typename Options, typename Grid, typename Layout>
class PaperLevel {
public:
    template <typename Dim>
    PaperLevel(const Dim& dim, int l, std::vector<Grid>& pyramid)
        : lm_(dim.model().levels[std::size_t(l)]), options_(dim.options()), pyramid_(pyramid), level_(l),
          layout_(lm_.shape, dim.model().channels, l, dim.levels()) {
        require_stride(layout_.stride(), lm_.matcher.get(), "matcher and neighbourhood shape", l);
    }
    const Shape& shape() const { return layout_.shape(); }
    std::size_t stride() const { return layout_.stride(); }
    std::unique_ptr<MatchScratch> make_scratch() const { return lm_.matcher->make_scratch(); }

protected:
    Grid& grid() const { return pyramid_[std::size_t(level_)]; }

    const LevelModelT& lm_;
    const Options& options_;
    std::vector<Grid>& pyramid_;
    const int level_;
    const Layout layout_;
};

template <typename Dim>
std::vector<typename Dim::Grid> synthesize_levels(const Dim& dim, const PaperRun& run) {
    using Grid = typename Dim::Grid;
    const int levels = dim.levels();
    std::vector<Grid> pyramid;
    uint64_t total = 0;
    for (int l = 0; l < levels; ++l) {
        pyramid.push_back(dim.make_level(l));
        total += Dim::stack(pyramid.back()).pixel_count();
    }
    if (run.trace) run.trace->assign(std::size_t(levels), {});
    const ProgressFn* report = run.progress && *run.progress ? run.progress : nullptr;
    std::atomic<bool> stop{false};
    std::atomic<uint64_t> done{0};
    const int threads = std::max(1, run.threads);

    for (int l = levels - 1; l >= 0; --l) {
        Grid& grid = pyramid[std::size_t(l)];
        Image& stack = Dim::stack(grid);
        const int width = stack.width, height = Dim::frame_height(grid);
        if (run.init == LevelInit::Noise || l + 1 == levels) {
            fill_matched_noise(stack, dim.histogram(l), run.seed, l);
        } else {
            const Grid& parent = pyramid[std::size_t(l + 1)];
            upsample_parent(Dim::stack(parent), Dim::frame_height(parent), stack, height);
        }
        typename Dim::Level level(dim, l, pyramid);
        std::vector<uint32_t>* trace = nullptr;
        if (run.trace) {
            trace = &(*run.trace)[std::size_t(l)];
            trace->assign(stack.pixel_count(), 0);
        }
        std::atomic<uint32_t> trace_counter{0};
        const Shape& shape = level.shape();
        // The wavefront needs room: tiny levels (the coarsest ones of a small
        // output) run on one thread, which gives the same bytes anyway.
        const bool parallel = threads > 1 && height >= 2 * causal_reach_y(shape) + 2 && !trace;
        const int workers = parallel ? std::min(threads, height) : 1;
        std::vector<RowProgress> progress(static_cast<std::size_t>(height));
        struct WorkerState {
            std::vector<uint8_t> query;
            std::unique_ptr<MatchScratch> scratch;
        };

        for (int t = 0; t < Dim::frames(grid); ++t) {
            for (auto& p : progress) p.done.store(0);
            level.begin_frame(t);
            const WavefrontScan scan{width, height, scan_lag(shape), causal_reach_x(shape), causal_reach_y(shape),
                                     wavefront_slack(width), parallel, &progress, &stop};
            run_rows(
                workers, height, stop, [&] { return WorkerState{std::vector<uint8_t>(level.stride()), level.make_scratch()}; },
                [&](int index, int y, WorkerState& state) {
                    const bool finished = scan_row(scan, y, [&](int x) {
                        level.visit(x, y, t, state.query.data(), state.scratch.get());
                        if (trace)
                            (*trace)[(std::size_t(t) * std::size_t(height) + std::size_t(y)) * std::size_t(width) +
                                     std::size_t(x)] = trace_counter.fetch_add(1);
                    });
                    if (!run.progress_per_row) return;
                    if (finished) done.fetch_add(uint64_t(width), std::memory_order_relaxed);
                    if (index == 0 && report && !(*report)(done.load(std::memory_order_relaxed), total))
                        stop.store(true);
                });
            if (!stop.load()) level.close_frame(t, threads);
            if (!run.progress_per_row) {
                done.fetch_add(uint64_t(width) * uint64_t(height));
                if (!stop.load() && report && !(*report)(done.load(), total)) stop.store(true);
            }
            if (stop.load()) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        level.close_level(threads);
    }
    return pyramid;
}

}  // namespace vqtex
