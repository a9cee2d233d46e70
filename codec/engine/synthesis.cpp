// synthesis.cpp - multiresolution raster synthesis of stills with a
// deterministic wavefront (paper sections 2.2-2.5): the still dimension of
// the paper engine's level driver (paper_levels.hpp) and its seam closing.
#include "engine/synthesis.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "engine/band_rematch.hpp"
#include "engine/paper_levels.hpp"
#include "engine/pyramid.hpp"

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

// Stills for the level driver (paper_levels.hpp): a level is one frame.
class StillLevels {
public:
    using Grid = Image;
    StillLevels(const TextureModel& model, const SynthesisOptions& options) : model_(model), options_(options) {}

    static Image& stack(Image& img) { return img; }
    static const Image& stack(const Image& img) { return img; }
    static int frame_height(const Image& img) { return img.height; }
    static int frames(const Image&) { return 1; }
    int levels() const { return int(model_.levels.size()); }
    Image make_level(int l) const {
        return Image(pyramid_level_size(options_.width, l), pyramid_level_size(options_.height, l), model_.channels);
    }
    const LevelHistogram& histogram(int l) const { return model_.levels[std::size_t(l)].histogram; }

    class Level {
    public:
        Level(const StillLevels& dim, int l, std::vector<Image>& pyramid)
            : lm_(dim.model_.levels[std::size_t(l)]), options_(dim.options_), pyramid_(pyramid), level_(l),
              layout_(lm_.shape, dim.model_.channels, l, dim.levels()), gather_(layout_, pyramid) {
            require_stride(layout_.stride(), lm_.matcher.get(), "matcher and neighbourhood shape", l);
        }
        const Shape& shape() const { return layout_.shape(); }
        std::size_t stride() const { return layout_.stride(); }
        std::unique_ptr<MatchScratch> make_scratch() const { return lm_.matcher->make_scratch(); }
        void begin_frame(int) {}
        void visit(int x, int y, int, uint8_t* query, MatchScratch* scratch) const {
            gather_.gather(x, y, query);
            const MatchContext context{pixel_salt(options_.seed, level_, 0, x, y), options_.tolerance};
            Image& img = pyramid_[std::size_t(level_)];
            copy_pixel(img.at(x, y), lm_.matcher->match(query, context, scratch), img.channels);
        }
        // Seam closing (band_rematch.hpp): the rows on both sides of the
        // top/bottom wrap, in place, with a symmetric neighbourhood.
        void close_frame(int, int threads) const {
            if (!lm_.closing) return;
            Image& img = pyramid_[std::size_t(level_)];
            const NeighborhoodLayout layout(lm_.closing_shape, img.channels, level_, int(pyramid_.size()));
            require_stride(layout.stride(), lm_.closing.get(), "seam matcher and shape", level_);
            const NeighborhoodGather gather(layout, pyramid_);
            Band band;
            band.slices = img.height;
            band.band = std::min(closing_band_rows(lm_.shape), (img.height + 1) / 2);
            band.visits = 2 * band.band;
            band.width = img.width;
            band.channels = img.channels;
            band.in_place = true;
            band.reach = layout.reach(0);
            rematch_band(
                band, *lm_.closing, layout.stride(), threads,
                [&](int sweep, int y, int, int x, uint8_t* query, MatchScratch* scratch) {
                    gather.gather(x, y, query);
                    const MatchContext context{pixel_salt(options_.seed, level_, 1 + sweep, x, y), options_.tolerance};
                    return lm_.closing->match(query, context, scratch);
                },
                [&](int y) { return img.at(0, y); });
        }
        void close_level(int) const {}

    private:
        const LevelModel& lm_;
        const SynthesisOptions& options_;
        std::vector<Image>& pyramid_;
        int level_;
        const NeighborhoodLayout layout_;
        const NeighborhoodGather gather_;
    };

private:
    const TextureModel& model_;
    const SynthesisOptions& options_;
};

}  // namespace

std::vector<Image> synthesize_pyramid(const TextureModel& model, const SynthesisOptions& options) {
    if (model.levels.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "texture model has no levels");
    if (options.width < 1 || options.height < 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size must be at least 1x1");
    PaperRun run;
    run.init = options.init;
    run.seed = options.seed;
    run.threads = options.threads;
    run.progress = &options.progress;
    run.progress_per_row = true;
    run.trace = options.trace ? &options.trace->visit_order : nullptr;
    return synthesize_levels(StillLevels(model, options), run);
}

}  // namespace vqtex
