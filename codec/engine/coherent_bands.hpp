// coherent_bands.hpp - the memory plan of the still coherent engine's
// output: the finest level synthesised whole and read through its
// positions, or for a large output in bands of rows read as they are done,
// so that neither its positions nor a second image are ever whole (the
// same bytes either way; Lefebvre & Hoppe 2005's passes read only a window
// around each pixel, so a band's inner rows are exact).
#pragma once

#include "common/image.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_synthesis.hpp"

namespace vqtex::coherent {

// The output of `options`' size from the analysis of the example less a
// frame of `margin` pixels on every side (copy_margin): the copies are laid
// out inside it, then moved into the whole example, whose frame the cuts
// and the read-out use. When the analysis is made level by level,
// `by_level_space` and `by_level_sets` are `space` and `sets`, whose
// levels the synthesis fills and empties. Returns the example's pixels
// through the positions, or with `readouts` each readout's.
std::vector<ReadImage> synthesize_pixels(const Image& example, int margin, const AppearanceSpace& space,
                                         const CoherenceSets& sets, const CoherentOptions& options,
                                         const std::vector<Readout>& readouts = {},
                                         AppearanceSpace* by_level_space = nullptr,
                                         CoherenceSets* by_level_sets = nullptr);

// The output of `options`' size laid out by quilting with blocks of
// options.quilt pixels (quilt.hpp) instead of the coherent passes, read as
// synthesize_pixels reads; `wraps`: the example tiles (the read-out's blend
// wraps across its edges). Needs no analysis; quilting holds at most
// quilt_memory beside the output.
std::vector<ReadImage> quilt_pixels(const Image& example, bool wraps, const CoherentOptions& options,
                                    const std::vector<Readout>& readouts = {});

}  // namespace vqtex::coherent
