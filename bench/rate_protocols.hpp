// vqtex-bench's codec protocols (docs/METRICS.md): at each rate point,
// vqtex's file decoded at the exemplar's size (same) and at 2x2 its area
// (large), beside every peer at or under the same byte budget (its decode
// as is, tiled, and synthesised by vqtex's engine and by G'MIC), ASTC at
// its fixed rates, and the ceilings: syntheses from the lossless exemplar.
#pragma once

#include "texture_run.hpp"

namespace vqtex_tools {

// The ceilings of the same and large protocols.
void run_ceilings(TextureRun& t);

// Every rate point's rows, ASTC's, and with --sheets their contact sheets.
// False when a vqtex encode or decode failed (reported on stderr).
bool run_rate_points(TextureRun& t);

}  // namespace vqtex_tools
