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
class StillLevels : public PaperDimension<TextureModel, SynthesisOptions> {
public:
    using PaperDimension::PaperDimension;
    using Grid = Image;
    static Image& stack(Image& img) { return img; }
    static const Image& stack(const Image& img) { return img; }
    static int frame_height(const Image& img) { return img.height; }
    static int frames(const Image&) { return 1; }
    Image make_level(int l) const {
        return Image(pyramid_level_size(options().width, l), pyramid_level_size(options().height, l),
                     model().channels);
    }

    class Level : public PaperLevel<LevelModel, SynthesisOptions, Image, NeighborhoodLayout> {
    public:
        Level(const StillLevels& dim, int l, std::vector<Image>& pyramid)
            : PaperLevel(dim, l, pyramid), gather_(layout_, pyramid) {}
        void begin_frame(int) {}
        void visit(int x, int y, int, uint8_t* query, MatchScratch* scratch) const {
            gather_.gather(x, y, query);
            const MatchContext context{pixel_salt(options_.seed, level_, 0, x, y), options_.tolerance};
            copy_pixel(grid().at(x, y), lm_.matcher->match(query, context, scratch), grid().channels);
        }
        // Seam closing (band_rematch.hpp): the rows on both sides of the
        // top/bottom wrap, in place, with a symmetric neighbourhood.
        void close_frame(int, int threads) const {
            if (!lm_.closing) return;
            Image& img = grid();
            const NeighborhoodLayout layout(lm_.closing_shape, img.channels, level_, int(pyramid_.size()));
            require_stride(layout.stride(), lm_.closing.get(), "seam matcher and shape", level_);
            const NeighborhoodGather gather(layout, pyramid_);
            Band band = seam_band(lm_.shape, img.width, img.height, img.channels);
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
        const NeighborhoodGather gather_;
    };
};

}  // namespace

std::vector<Image> synthesize_pyramid(const TextureModel& model, const SynthesisOptions& options) {
    if (model.levels.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "texture model has no levels");
    if (options.width < 1 || options.height < 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size must be at least 1x1");
    PaperRun run = paper_run(options);
    run.progress_per_row = true;
    run.trace = options.trace ? &options.trace->visit_order : nullptr;
    return synthesize_levels(StillLevels(model, options), run);
}

}  // namespace vqtex
