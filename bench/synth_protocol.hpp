// vqtex-bench's synth protocol: vqtex's engine and G'MIC's
// syntexturize_matchpatch each synthesise from the lossless exemplar, and
// both outputs are scored against the held-out crop (docs/METRICS.md, "The
// synth protocol").
#pragma once

#include "texture_run.hpp"

namespace vqtex_tools {

// The synth protocol's rows of one photograph, and with --sheets its
// contact sheet and seam maps.
void run_synth_protocol(TextureRun& t);

}  // namespace vqtex_tools
