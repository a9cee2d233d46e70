// temporal_synthesis.hpp - the synthesis engine for temporal textures
// (paper section 5.2): "the synthesis progresses from lower to higher
// resolutions, and within each resolution the output is synthesized slice by
// slice along the time domain".
//
// Per level, coarsest first: the level starts as histogram-matched noise
// (coarsest level, or every level with LevelInit::Noise) or as the finished
// coarser level upsampled; then frames t = 0 .. N-1 are synthesised in order,
// each in the 2D engine's rotated raster order (row y starts at column
// y * lag mod width) with a causal {RxCxD,k} neighbourhood. Everything wraps
// in x, y and t, so the output tiles in space and loops in time.
//
// Loop closing. Frame 0 is synthesised before the last frames exist: through
// the temporal wrap it reads their initial values, so the last frame and the
// first do not quite meet (the temporal analogue of the 2D engine's seam
// closing; both run band_rematch.hpp). Once a level is done, the frames on both sides of
// the wrap are matched again with a symmetric neighbourhood (the full RxCxD
// window, previous and next frames alike), frame by frame from the earlier
// side of the band across the wrap, twice.
//
// Frame-seam closing. Within a frame the raster scan starts at the top: the
// first rows read, through the top/bottom wrap, the last rows' initial
// values, so the frame would not tile in y (and row 0, which starts at
// column 0, not quite in x). As in the 2D engine (band_rematch.hpp), the rows
// on both sides of that wrap are matched again once the frame is done, with
// a shape that sees the whole RxC window of the current frame (rows above
// and below alike) but, like the causal one, only the previous frames: the
// next frame is synthesised after the closing and reads the closed rows, so
// the closing does not break temporal coherence. Two sweeps, from the upper
// side of the band down across the wrap, in place on one thread.
//
// Still pixels. With a previous frame in the shape, every entry of a level's
// matchers carries the example pixel's value one frame earlier (its key,
// neighborhood3d.hpp). Where the entry chosen shows the example pixel did
// not change, the output pixel does not change either: it keeps its own
// previous value, not the entry's. (Copying the entry instead re-quantises
// the frame through the lossy codebooks at every step, and a still example
// gave an output drifting by 8-14% of its variance per frame.) Whatever the
// codebook, a still example then gives a still output, exactly, and still
// parts of an example stay still; where the example moves, entries are
// copied as in the paper. The rule is off for frame 0 of the causal scan,
// whose previous frame is still an initial value.
//
// Determinism: within a frame, rows run as a wavefront on several threads
// (each read sees a finished pixel or one still holding its initial value
// under any thread count); the closing pass computes each frame from the
// state before that frame's update. The salt of a pixel's near-tie and entry
// choices depends on (seed, level, pass, x, y) but not on t, so a pixel whose
// neighbourhood does not change from one frame to the next keeps its value.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/matcher.hpp"
#include "engine/neighborhood3d.hpp"
#include "engine/noise.hpp"
#include "engine/synthesis.hpp"
#include "engine/volume.hpp"

namespace vqtex {

struct VolumeLevelModel {
    Shape shape;
    LevelHistogram histogram;
    std::shared_ptr<const Matcher> matcher;
    Shape closing_shape;                      // symmetric
    std::shared_ptr<const Matcher> closing;    // may be null: no loop closing at this level
    Shape seam_shape;                         // whole-frame: symmetric in space, causal in time
    std::shared_ptr<const Matcher> seam;       // may be null: no frame-seam closing at this level
};

struct VolumeModel {
    int channels = 0;
    std::vector<VolumeLevelModel> levels;  // [0] = finest
};

struct VolumeSynthesisOptions {
    LevelInit init = LevelInit::Parent;
    uint32_t tolerance = 0;
    int width = 0, height = 0, frames = 0;
    uint64_t seed = 0;
    int threads = 1;
    ProgressFn progress;
    // For tests: per level, the order in which the causal scan visited each
    // voxel ((t * height + y) * width + x).
    std::vector<std::vector<uint32_t>>* trace = nullptr;
};

// Frames on each side of the temporal wrap that loop closing re-matches.
int closing_band_frames(const Shape& causal_shape, int frames);

// The whole output pyramid, [0] = the finest (the animation itself).
std::vector<Volume> synthesize_volume_pyramid(const VolumeModel& model, const VolumeSynthesisOptions& options);

}  // namespace vqtex
