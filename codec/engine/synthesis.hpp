// synthesis.hpp - the multiresolution synthesis engine (paper sections 2-3).
//
// A TextureModel is everything synthesis needs per pyramid level: the
// neighbourhood shape, the histogram that seeds the noise and a matcher (the
// exhaustive example search, or a TSVQ codebook). The engine synthesises the
// output pyramid coarsest level first, every level toroidal, so the result of
// any size tiles seamlessly.
//
// Scan order. Within a level the pixels are visited row by row, top to bottom;
// row y starts at column (y * lag) mod width and wraps around. The rotation
// is what lets rows run in parallel as a wavefront (row y needs only the first
// lag + C/2 + 1 pixels of row y-1 before it can start, instead of the whole
// row, because its left neighbours at the start never wrap back into the end
// of the row above). Every read either sees a finished pixel or a pixel that
// is still noise under any thread count, so the output is the same bytes on
// one thread or many.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "common/image.hpp"
#include "engine/matcher.hpp"
#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"

namespace vqtex {

struct LevelModel {
    Shape shape;
    LevelHistogram histogram;
    std::shared_ptr<const Matcher> matcher;
    // Optional seam closing: a symmetric-neighbourhood matcher run over the
    // rows on both sides of the top/bottom wrap once the level is done.
    Shape closing_shape;
    std::shared_ptr<const Matcher> closing;
};

struct TextureModel {
    int channels = 0;
    std::vector<LevelModel> levels;  // [0] = finest
};

// Return false to cancel.
using ProgressFn = std::function<bool(uint64_t done, uint64_t total)>;

// For tests: the order in which the engine visited the pixels of each level.
struct SynthesisTrace {
    std::vector<std::vector<uint32_t>> visit_order;  // per level, per pixel
};

struct SynthesisOptions {
    LevelInit init = LevelInit::Parent;
    // Near-tie tolerance in 1/256 of the best distance (see MatchContext).
    uint32_t tolerance = 0;
    int width = 0;
    int height = 0;
    uint64_t seed = 0;
    int threads = 1;
    ProgressFn progress;
    SynthesisTrace* trace = nullptr;
};

// Rows on each side of the top/bottom wrap that seam closing re-synthesises.
int closing_band_rows(const Shape& causal_shape);

// Column at which row y of a level starts, and the rotation per row.
int scan_lag(const Shape& shape);
int row_start(int y, int lag, int width);

// The per-pixel salt for near-tie choices: a function of seed, level, pass
// and position only.
uint64_t pixel_salt(uint64_t seed, int level, int pass, int x, int y);

// The whole output pyramid, [0] = finest (the texture itself).
std::vector<Image> synthesize_pyramid(const TextureModel& model, const SynthesisOptions& options);

}  // namespace vqtex
