// The animation protocol's printed summary (docs/BENCHMARKS.md, "The
// animation protocol"): per animation, the example's own figures and every
// row's measures; for each vqtex row its SWD and coherence over the
// ceiling's, and whether it is at or below its av1+synth row on each.
#pragma once

#include <vector>

#include "animation_rows.hpp"

namespace vqtex_tools {

void print_animation_summary(const std::vector<AnimRow>& rows);

}  // namespace vqtex_tools
