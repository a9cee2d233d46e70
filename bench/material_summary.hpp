// The printed summary of vqtex-bench's materials protocol (docs/METRICS.md,
// "The materials protocol").
#pragma once

#include <cstdint>
#include <vector>

#include "material_rows.hpp"

namespace vqtex_tools {

// At the default quality, per set: each map's scores in the set and alone,
// each pair's luminance correlation (the example's, and each mode's
// difference from it) and the normal map's shading; then per rate point the
// means over the sets. `side` and `output_side` are the maps' and the
// outputs' side, for the title.
void print_material_summary(const std::vector<MaterialRow>& rows, int side, int output_side, uint64_t seed);

}  // namespace vqtex_tools
