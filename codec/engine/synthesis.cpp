// synthesis.cpp - multiresolution raster synthesis with a deterministic
// wavefront (paper sections 2.2-2.5).
#include "engine/synthesis.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "common/error.hpp"
#include "engine/pyramid.hpp"
#include "engine/wavefront.hpp"

namespace vqtex {

int scan_lag(const Shape& shape) { return causal_reach_x(shape) + 1; }

int closing_band_rows(const Shape& causal_shape) { return 2 * causal_reach_y(causal_shape) + 1; }

uint64_t pixel_salt(uint64_t seed, int level, int pass, int x, int y) {
    return candidate_rank(seed ^ (uint64_t(uint32_t(level * 4 + pass)) << 56),
                          uint32_t(y) * 65537u ^ uint32_t(x) * 0x9E3779B1u);
}

int row_start(int y, int lag, int width) {
    return int((int64_t(y) * lag) % width);
}

namespace {

// Pixel replication: each pixel takes its parent's value, the same parent
// (x >> 1, y >> 1) the neighbourhoods use.
void upsample_parent(const Image& parent, Image& img) {
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            copy_pixel(img.at(x, y), parent.at(x >> 1, y >> 1), img.channels);
}

// Shared state of one level's wavefront.
struct LevelRun {
    WavefrontScan scan;
    const NeighborhoodGather* gather;
    const Matcher* matcher;
    std::vector<Image>* pyramid;
    int level;
    std::atomic<uint64_t>* pixels_done;
    std::vector<uint32_t>* trace;
    std::atomic<uint32_t>* trace_counter;
    uint64_t seed;
    uint32_t tolerance;
};

// Synthesise row y of the level.
void run_row(const LevelRun& r, int y, std::vector<uint8_t>& query, MatchScratch* scratch) {
    Image& out = (*r.pyramid)[std::size_t(r.level)];
    const int w = r.scan.width;
    const bool finished = scan_row(r.scan, y, [&](int x) {
        r.gather->gather(x, y, query.data());
        const MatchContext context{pixel_salt(r.seed, r.level, 0, x, y), r.tolerance};
        const uint8_t* pixel = r.matcher->match(query.data(), context, scratch);
        copy_pixel(out.at(x, y), pixel, out.channels);
        if (r.trace) (*r.trace)[std::size_t(y) * w + x] = r.trace_counter->fetch_add(1);
    });
    if (finished) r.pixels_done->fetch_add(uint64_t(w), std::memory_order_relaxed);
}

// Seam closing. A causal scan on a torus must start somewhere: the first rows
// are synthesised before the last ones exist and read the initial values
// through the wrap, so the bottom and the top rows do not quite meet. Once
// the level is complete, the rows on both sides of that line are matched
// again with a symmetric neighbourhood, which sees the finished pixels above
// and below, from the upper side of the band down across the wrap. Two
// sweeps: the second sees the first's results on both sides.
//
// With two threads the sweeps overlap. The second sweep may rewrite band row
// k once the first has finished row k + reach: by then every read of row k
// by the first sweep is done, and the rows below k that the second sweep
// reads hold their final first-sweep values. So the bytes are those of the
// sequential order; only the waiting differs.
void close_seam(const LevelModel& lm, std::vector<Image>& pyramid, int level, int levels,
                int channels, const SynthesisOptions& options, int threads) {
    Image& img = pyramid[std::size_t(level)];
    const NeighborhoodLayout layout(lm.closing_shape, channels, level, levels);
    if (layout.stride() != lm.closing->stride())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "seam matcher and shape disagree at level " +
                                               std::to_string(level));
    const int band = std::min(closing_band_rows(lm.shape), (img.height + 1) / 2);
    const int rows = 2 * band;
    const int reach = layout.reach(0);
    const NeighborhoodGather gather(layout, pyramid);
    std::atomic<int> first_sweep_rows{0};
    // The first sweep always runs to its end (or releases the second when it
    // fails), so the second waits for it unconditionally.
    const std::atomic<bool> never_stopped{false};
    auto sweep = [&](int pass, bool wait_for_first) {
        std::vector<uint8_t> query(layout.stride());
        std::unique_ptr<MatchScratch> scratch = lm.closing->make_scratch();
        for (int k = 0; k < rows; ++k) {
            if (wait_for_first) wait_for(first_sweep_rows, std::min(rows, k + reach + 1), never_stopped);
            const int y = Image::wrap(img.height - band + k, img.height);
            for (int x = 0; x < img.width; ++x) {
                gather.gather(x, y, query.data());
                const MatchContext context{pixel_salt(options.seed, level, 1 + pass, x, y), options.tolerance};
                copy_pixel(img.at(x, y), lm.closing->match(query.data(), context, scratch.get()), img.channels);
            }
            if (pass == 0) first_sweep_rows.store(k + 1, std::memory_order_release);
        }
    };
    // Overlap only when the band and the windows around it do not meet
    // themselves across the torus (every band row a distinct image row).
    if (threads > 1 && rows + 2 * reach + 2 <= img.height) {
        std::exception_ptr second_failed;
        std::thread second([&] {
            try {
                sweep(1, true);
            } catch (...) {
                second_failed = std::current_exception();
            }
        });
        try {
            sweep(0, false);
        } catch (...) {
            first_sweep_rows.store(rows);  // release the second sweep
            second.join();
            throw;
        }
        second.join();
        if (second_failed) std::rethrow_exception(second_failed);
    } else {
        sweep(0, false);
        sweep(1, false);
    }
}

}  // namespace

std::vector<Image> synthesize_pyramid(const TextureModel& model, const SynthesisOptions& options) {
    const int levels = int(model.levels.size());
    if (levels < 1) fail(VQTEX_ERROR_INVALID_ARGUMENT, "texture model has no levels");
    if (options.width < 1 || options.height < 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size must be at least 1x1");

    std::vector<Image> pyramid;
    uint64_t total_pixels = 0;
    for (int l = 0; l < levels; ++l) {
        pyramid.emplace_back(pyramid_level_size(options.width, l),
                             pyramid_level_size(options.height, l), model.channels);
        total_pixels += pyramid.back().pixel_count();
    }
    if (options.trace) options.trace->visit_order.assign(std::size_t(levels), {});

    std::atomic<bool> stop{false};
    std::atomic<uint64_t> pixels_done{0};
    const int threads = std::max(1, options.threads);

    for (int l = levels - 1; l >= 0; --l) {
        const LevelModel& lm = model.levels[std::size_t(l)];
        Image& img = pyramid[std::size_t(l)];
        if (options.init == LevelInit::Noise || l + 1 == levels)
            fill_matched_noise(img, lm.histogram, options.seed, l);
        else
            upsample_parent(pyramid[std::size_t(l + 1)], img);
        const NeighborhoodLayout layout(lm.shape, model.channels, l, levels);
        if (layout.stride() != lm.matcher->stride())
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "matcher and neighbourhood shape disagree at level " +
                                                   std::to_string(l));

        std::vector<RowProgress> progress(std::size_t(img.height));
        std::atomic<uint32_t> trace_counter{0};
        std::vector<uint32_t>* trace = nullptr;
        if (options.trace) {
            trace = &options.trace->visit_order[std::size_t(l)];
            trace->assign(img.pixel_count(), 0);
        }
        const Shape& shape = layout.shape();
        const NeighborhoodGather gather(layout, pyramid);
        // The wavefront needs room: tiny levels (the coarsest ones of a small
        // output) run on one thread, which gives the same bytes anyway.
        const bool parallel = threads > 1 && img.height >= 2 * causal_reach_y(shape) + 2 && !options.trace;
        const int workers = parallel ? std::min(threads, img.height) : 1;
        const LevelRun run{{img.width, img.height, scan_lag(shape), causal_reach_x(shape), causal_reach_y(shape),
                            wavefront_slack(img.width), parallel, &progress, &stop},
                           &gather, lm.matcher.get(), &pyramid, l, &pixels_done, trace, &trace_counter,
                           options.seed, options.tolerance};
        struct WorkerState {
            std::vector<uint8_t> query;
            std::unique_ptr<MatchScratch> scratch;
        };
        run_rows(
            workers, img.height, stop,
            [&] { return WorkerState{std::vector<uint8_t>(layout.stride()), lm.matcher->make_scratch()}; },
            [&](int index, int y, WorkerState& state) {
                run_row(run, y, state.query, state.scratch.get());
                if (index == 0 && options.progress &&
                    !options.progress(pixels_done.load(std::memory_order_relaxed), total_pixels))
                    stop.store(true);
            });
        if (lm.closing && !stop.load()) close_seam(lm, pyramid, l, levels, model.channels, options, threads);
        if (stop.load()) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    }
    return pyramid;
}

}  // namespace vqtex
