// compact_protocol.hpp - vqtex-bench's compact protocol (docs/BENCHMARKS.md
// "The compact protocol"): files sized by the texture, not by the input.
//
// Each image of the folder is the whole example (a 1024x1024 or 2048x2048
// game texture); every output is decoded at the input's size and scored
// against the input itself: completeness, SWD, coherence and coherence at
// half resolution (docs/METRICS.md). Rows per rate point (--target-sizes,
// default 4, 8, 16 and 32 KB, and the default quality):
//   vqtex          the file the encoder writes;
//   avif+synth     the whole input as AVIF at the vqtex file's bytes,
//                  synthesised by vqtex's engine;
//   vqtex-crop     the encoder's rule for inputs larger than its budget
//                  before it coded parts of large examples: the whole input
//                  at the finest level that fits, else its largest top-left
//                  crop (at the default: the whole input at 4 KB per
//                  128x128, the rule's own budget);
// and once per image the ceiling, synthesis from the lossless input.
// Encodes run on 2 threads; encode time and peak memory are the encode's.
// An image of at most 256x256 is instead tiled 4x4 and both the tile and
// the tiling are encoded at the default: their bytes, and the tiling's
// decode scored against the tile.
#pragma once

#include "bench_options.hpp"

namespace vqtex_tools {

int run_compact_protocol(const BenchOptions& o);

}  // namespace vqtex_tools
