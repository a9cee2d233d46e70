// temporal_synthesis.cpp - frame-by-frame causal synthesis of a volume
// pyramid, coarse to fine, with loop closing around the temporal wrap (paper
// section 5.2).
#include "engine/temporal_synthesis.hpp"

#include <algorithm>
#include <atomic>
#include <thread>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/wavefront.hpp"

namespace vqtex {

int closing_band_frames(const Shape& causal_shape, int frames) {
    return std::min(causal_shape.frames / 2 + 1, std::max(1, frames / 2));
}

namespace {

constexpr int kClosingSweeps = 2;

// Each voxel takes its parent's value (x >> 1, y >> 1, t >> 1), the ancestor
// the neighbourhoods use.
void upsample_parent(const Volume& parent, Volume& v) {
    for (int t = 0; t < v.frames; ++t)
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                std::copy(parent.at(x >> 1, y >> 1, t >> 1), parent.at(x >> 1, y >> 1, t >> 1) + v.channels,
                          v.at(x, y, t));
}

uint64_t voxel_salt(uint64_t seed, int level, int pass, int x, int y) {
    // Not a function of t: see temporal_synthesis.hpp.
    return pixel_salt(seed ^ 0x74656D706F72616Cull /* "temporal" */, level, pass, x, y);
}

// The matchers of a level whose shape reads the previous frame return the
// example pixel followed by the same pixel one frame earlier (its entry key,
// neighborhood3d.hpp). Equal: the example did not change there.
bool still_in_example(const uint8_t* entry, int channels) {
    return std::equal(entry, entry + channels, entry + channels);
}

// Shared state of one frame's wavefront (wavefront.hpp, as a still level's).
struct FrameRun {
    WavefrontScan scan;
    const NeighborhoodLayout3* layout;
    const Matcher* matcher;
    std::vector<Volume>* pyramid;
    bool keep_still;  // the pixel's previous frame is final (not an initial value)
    int level, t;
    uint64_t seed;
    uint32_t tolerance;
    std::vector<uint32_t>* trace;
    std::atomic<uint32_t>* trace_counter;
};

void run_row(const FrameRun& r, int y, std::vector<uint8_t>& query, MatchScratch* scratch) {
    Volume& v = (*r.pyramid)[std::size_t(r.level)];
    const int w = v.width;
    scan_row(r.scan, y, [&](int x) {
        r.layout->gather(*r.pyramid, x, y, r.t, query.data());
        const MatchContext context{voxel_salt(r.seed, r.level, 0, x, y), r.tolerance};
        const uint8_t* pixel = r.matcher->match(query.data(), context, scratch);
        if (r.keep_still && still_in_example(pixel, v.channels)) pixel = v.wrapped(x, y, r.t - 1);
        copy_pixel(v.at(x, y, r.t), pixel, v.channels);
        if (r.trace)
            (*r.trace)[(std::size_t(r.t) * std::size_t(v.height) + std::size_t(y)) * std::size_t(w) + std::size_t(x)] =
                r.trace_counter->fetch_add(1);
    });
}

// Loop closing at one finished level (see temporal_synthesis.hpp). Each
// frame's new values are computed from the volume as it was before that
// frame's update, so rows can run on any number of threads.
void close_loop(const VolumeLevelModel& lm, std::vector<Volume>& pyramid, int level, int levels, int channels,
                const VolumeSynthesisOptions& options) {
    Volume& v = pyramid[std::size_t(level)];
    const NeighborhoodLayout3 layout(lm.closing_shape, channels, level, levels);
    if (layout.stride() != lm.closing->stride())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "loop-closing matcher and shape disagree at level " + std::to_string(level));
    const int band = closing_band_frames(lm.shape, v.frames);
    const bool keep_still = layout.predecessor_offset() >= 0;
    const std::size_t ch = std::size_t(channels), row_bytes = std::size_t(v.width) * ch;
    std::vector<uint8_t> updated(v.frame_pixels() * ch);
    for (int sweep = 0; sweep < kClosingSweeps; ++sweep) {
        for (int k = 0; k < 2 * band && k < v.frames; ++k) {
            const int t = Image::wrap(v.frames - band + k, v.frames);
            parallel_for(options.threads, std::size_t(v.height), 4, [&](std::size_t y0, std::size_t y1) {
                std::vector<uint8_t> query(layout.stride());
                std::unique_ptr<MatchScratch> scratch = lm.closing->make_scratch();
                for (std::size_t y = y0; y < y1; ++y)
                    for (int x = 0; x < v.width; ++x) {
                        layout.gather(pyramid, x, int(y), t, query.data());
                        const MatchContext context{voxel_salt(options.seed, level, 1 + sweep, x, int(y)),
                                                   options.tolerance};
                        const uint8_t* pixel = lm.closing->match(query.data(), context, scratch.get());
                        if (keep_still && still_in_example(pixel, channels)) pixel = v.wrapped(x, int(y), t - 1);
                        std::copy(pixel, pixel + ch, updated.data() + y * row_bytes + std::size_t(x) * ch);
                    }
            });
            std::copy(updated.begin(), updated.end(), v.frame_data(t));
        }
    }
}

// Frame-seam closing of frame t (see temporal_synthesis.hpp).
void close_frame_seam(const VolumeLevelModel& lm, std::vector<Volume>& pyramid, int level, int levels, int channels,
                      int t, bool keep_still, const VolumeSynthesisOptions& options) {
    Volume& v = pyramid[std::size_t(level)];
    const NeighborhoodLayout3 layout(lm.seam_shape, channels, level, levels);
    if (layout.stride() != lm.seam->stride())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "frame-seam matcher and shape disagree at level " + std::to_string(level));
    // The rows a frame's seam band spans are the still engine's (one frame's
    // causal window, time aside).
    const Shape frame_shape{lm.shape.rows, lm.shape.cols, lm.shape.levels};
    const int band = std::min(closing_band_rows(frame_shape), (v.height + 1) / 2);
    keep_still = keep_still && layout.predecessor_offset() >= 0;
    std::vector<uint8_t> query(layout.stride());
    std::vector<uint8_t> row(std::size_t(v.width) * std::size_t(channels));
    std::unique_ptr<MatchScratch> scratch = lm.seam->make_scratch();
    // Each row is computed from the frame as it was before that row's
    // update: no column is visited first, so the closing itself leaves no
    // trace at x = 0.
    for (int sweep = 0; sweep < kClosingSweeps; ++sweep)
        for (int k = 0; k < 2 * band; ++k) {
            const int y = Image::wrap(v.height - band + k, v.height);
            for (int x = 0; x < v.width; ++x) {
                layout.gather(pyramid, x, y, t, query.data());
                const MatchContext context{voxel_salt(options.seed ^ 0x7365616Dull /* "seam" */, level, 1 + sweep, x, y),
                                           options.tolerance};
                const uint8_t* pixel = lm.seam->match(query.data(), context, scratch.get());
                if (keep_still && still_in_example(pixel, channels)) pixel = v.wrapped(x, y, t - 1);
                std::copy(pixel, pixel + channels, row.data() + std::size_t(x) * std::size_t(channels));
            }
            std::copy(row.begin(), row.end(), v.at(0, y, t));
        }
}

}  // namespace

std::vector<Volume> synthesize_volume_pyramid(const VolumeModel& model, const VolumeSynthesisOptions& options) {
    const int levels = int(model.levels.size());
    if (levels < 1) fail(VQTEX_ERROR_INVALID_ARGUMENT, "temporal texture model has no levels");
    if (options.width < 1 || options.height < 1 || options.frames < 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output must have at least 1x1 pixels and 1 frame");

    std::vector<Volume> pyramid;
    uint64_t total = 0;
    for (int l = 0; l < levels; ++l) {
        pyramid.emplace_back(pyramid_level_size(options.width, l), pyramid_level_size(options.height, l),
                             pyramid_level_size(options.frames, l), model.channels);
        total += pyramid.back().voxel_count();
    }
    if (options.trace) options.trace->assign(std::size_t(levels), {});
    std::atomic<bool> stop{false};
    uint64_t done = 0;
    const int threads = std::max(1, options.threads);

    for (int l = levels - 1; l >= 0; --l) {
        const VolumeLevelModel& lm = model.levels[std::size_t(l)];
        Volume& v = pyramid[std::size_t(l)];
        if (options.init == LevelInit::Noise || l + 1 == levels)
            fill_matched_noise(v.stack, lm.histogram, options.seed, l);
        else
            upsample_parent(pyramid[std::size_t(l + 1)], v);
        const NeighborhoodLayout3 layout(lm.shape, model.channels, l, levels);
        if (!lm.matcher || layout.stride() != lm.matcher->stride())
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "matcher and neighbourhood shape disagree at level " + std::to_string(l));
        std::vector<uint32_t>* trace = nullptr;
        if (options.trace) {
            trace = &(*options.trace)[std::size_t(l)];
            trace->assign(v.voxel_count(), 0);
        }
        std::atomic<uint32_t> trace_counter{0};
        const Shape& shape = layout.shape();
        const int reach_x = shape.cols / 2, reach_y = shape.rows / 2;
        const int lag = reach_x + 1;
        const bool parallel = threads > 1 && v.height >= 2 * reach_y + 2 && !options.trace;
        const int workers = parallel ? std::min(threads, v.height) : 1;
        std::vector<RowProgress> progress(std::size_t(v.height));
        struct WorkerState {
            std::vector<uint8_t> query;
            std::unique_ptr<MatchScratch> scratch;
        };

        for (int t = 0; t < v.frames; ++t) {
            for (auto& p : progress) p.done.store(0);
            const bool keep_still = t > 0 && layout.predecessor_offset() >= 0;
            const FrameRun run{{v.width, v.height, lag, reach_x, reach_y, wavefront_slack(v.width), parallel,
                                &progress, &stop},
                               &layout, lm.matcher.get(), &pyramid, keep_still, l, t, options.seed,
                               options.tolerance, trace, &trace_counter};
            run_rows(
                workers, v.height, stop,
                [&] { return WorkerState{std::vector<uint8_t>(layout.stride()), lm.matcher->make_scratch()}; },
                [&](int, int y, WorkerState& state) { run_row(run, y, state.query, state.scratch.get()); });
            if (lm.seam && !stop.load()) close_frame_seam(lm, pyramid, l, levels, model.channels, t, keep_still, options);
            done += v.frame_pixels();
            if (!stop.load() && options.progress && !options.progress(done, total)) stop.store(true);
            if (stop.load()) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        }
        if (lm.closing) close_loop(lm, pyramid, l, levels, model.channels, options);
    }
    return pyramid;
}

}  // namespace vqtex
