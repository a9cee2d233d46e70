// temporal_synthesis.cpp - frame-by-frame causal synthesis of a volume
// pyramid, coarse to fine, with loop closing around the temporal wrap (paper
// section 5.2): the animated dimension of the paper engine's level driver
// (paper_levels.hpp), its frame-seam and loop closings.
#include "engine/temporal_synthesis.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "engine/band_rematch.hpp"
#include "engine/paper_levels.hpp"

namespace vqtex {

int closing_band_frames(const Shape& causal_shape, int frames) {
    return std::min(causal_shape.frames / 2 + 1, std::max(1, frames / 2));
}

namespace {

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

// Animations for the level driver (paper_levels.hpp): a level is a stack of
// frames, scanned in order.
class AnimatedLevels : public PaperDimension<VolumeModel, VolumeSynthesisOptions> {
public:
    using PaperDimension::PaperDimension;
    using Grid = Volume;
    static Image& stack(Volume& v) { return v.stack; }
    static const Image& stack(const Volume& v) { return v.stack; }
    static int frame_height(const Volume& v) { return v.height; }
    static int frames(const Volume& v) { return v.frames; }
    Volume make_level(int l) const {
        return Volume(pyramid_level_size(options().width, l), pyramid_level_size(options().height, l),
                      pyramid_level_size(options().frames, l), model().channels);
    }

    class Level : public PaperLevel<VolumeLevelModel, VolumeSynthesisOptions, Volume, NeighborhoodLayout3> {
    public:
        using PaperLevel::PaperLevel;
        // The still-pixel rule is off for frame 0, whose previous frame is
        // still an initial value.
        void begin_frame(int t) { keep_still_ = t > 0 && layout_.predecessor_offset() >= 0; }
        void visit(int x, int y, int t, uint8_t* query, MatchScratch* scratch) const {
            layout_.gather(pyramid_, x, y, t, query);
            const MatchContext context{voxel_salt(options_.seed, level_, 0, x, y), options_.tolerance};
            copy_pixel(grid().at(x, y, t), keep_or_match(*lm_.matcher, keep_still_, query, context, scratch, x, y, t),
                       grid().channels);
        }
        // Frame-seam closing of frame t (temporal_synthesis.hpp): the rows on
        // both sides of the frame's top/bottom wrap, row by row. The rows
        // the band spans are the still engine's (one frame's causal window,
        // time aside).
        void close_frame(int t, int threads) const {
            if (!lm_.seam) return;
            Volume& v = grid();
            const NeighborhoodLayout3 layout(lm_.seam_shape, v.channels, level_, int(pyramid_.size()));
            require_stride(layout.stride(), lm_.seam.get(), "frame-seam matcher and shape", level_);
            const bool keep_still = keep_still_ && layout.predecessor_offset() >= 0;
            const Shape frame_shape{lm_.shape.rows, lm_.shape.cols, lm_.shape.levels};
            rematch_band(
                seam_band(frame_shape, v.width, v.height, v.channels), *lm_.seam, layout.stride(), threads,
                [&](int sweep, int y, int, int x, uint8_t* query, MatchScratch* scratch) {
                    layout.gather(pyramid_, x, y, t, query);
                    const uint64_t seam_seed = options_.seed ^ 0x7365616Dull /* "seam" */;
                    const MatchContext context{voxel_salt(seam_seed, level_, 1 + sweep, x, y), options_.tolerance};
                    return keep_or_match(*lm_.seam, keep_still, query, context, scratch, x, y, t);
                },
                [&](int y) { return v.at(0, y, t); });
        }
        // Loop closing (temporal_synthesis.hpp): the frames on both sides of
        // the temporal wrap, frame by frame.
        void close_level(int threads) const {
            if (!lm_.closing) return;
            Volume& v = grid();
            const NeighborhoodLayout3 layout(lm_.closing_shape, v.channels, level_, int(pyramid_.size()));
            require_stride(layout.stride(), lm_.closing.get(), "loop-closing matcher and shape", level_);
            const bool keep_still = layout.predecessor_offset() >= 0;
            Band band;
            band.slices = v.frames;
            band.band = closing_band_frames(lm_.shape, v.frames);
            band.visits = std::min(2 * band.band, v.frames);
            band.rows = v.height;
            band.width = v.width;
            band.channels = v.channels;
            rematch_band(
                band, *lm_.closing, layout.stride(), threads,
                [&](int sweep, int t, int y, int x, uint8_t* query, MatchScratch* scratch) {
                    layout.gather(pyramid_, x, y, t, query);
                    const MatchContext context{voxel_salt(options_.seed, level_, 1 + sweep, x, y), options_.tolerance};
                    return keep_or_match(*lm_.closing, keep_still, query, context, scratch, x, y, t);
                },
                [&](int t) { return v.frame_data(t); });
        }

    private:
        // The matcher's pixel, or the output's own previous value where the
        // entry shows the example did not change (temporal_synthesis.hpp).
        const uint8_t* keep_or_match(const Matcher& matcher, bool keep_still, const uint8_t* query,
                                     const MatchContext& context, MatchScratch* scratch, int x, int y, int t) const {
            const uint8_t* pixel = matcher.match(query, context, scratch);
            return keep_still && still_in_example(pixel, grid().channels) ? grid().wrapped(x, y, t - 1) : pixel;
        }

        bool keep_still_ = false;
    };
};

}  // namespace

std::vector<Volume> synthesize_volume_pyramid(const VolumeModel& model, const VolumeSynthesisOptions& options) {
    if (model.levels.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "temporal texture model has no levels");
    if (options.width < 1 || options.height < 1 || options.frames < 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output must have at least 1x1 pixels and 1 frame");
    PaperRun run = paper_run(options);
    run.trace = options.trace;
    return synthesize_levels(AnimatedLevels(model, options), run);
}

}  // namespace vqtex
