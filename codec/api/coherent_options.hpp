// coherent_options.hpp - the coherent engine's options (Lefebvre & Hoppe
// 2005's synthesis by example coordinates, engine/coherent_synthesis.hpp)
// from the engine's parameters as an atlas file stores them
// (format/atlas_file.hpp): the one place where parameters become options,
// for the decoder of atlas files and for vqtex_synthesize alike, so that a
// file decodes to what synthesis from its atlas gives.
#pragma once

#include <cstdint>

#include "engine/coherent_synthesis.hpp"
#include "format/atlas_file.hpp"

namespace vqtex {

// The engine's options for `params` at an output size and seed (the rest
// left at CoherentOptions' defaults: threads 1, no progress).
CoherentOptions coherent_options(const AtlasSynthesisParams& params, int width, int height, uint64_t seed);

}  // namespace vqtex
