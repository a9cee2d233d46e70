// animation_protocol.hpp - vqtex-bench's animation protocol
// (docs/BENCHMARKS.md "The animation protocol"): animated textures from a
// file, against their example sequence.
//
// The animations (anim_examples.hpp): the folder's NAME_anim/ sequences,
// decoded at twice their side, and, when the shared corpus is found
// (--shared, default the source tree's ../shared/corpus), 128x128x32 loops
// made from two of its photographs (water, caustics), decoded at
// 128x128. Every output has --frames frames (default 64), seed --seed.
// Rows per animation:
//   ceiling    vqtex_synthesize_volume from the lossless example frames;
//   vqtex      vqtex_encode_volume at the default quality and at each
//              --target-sizes (default 4000, 16000, 64000 bytes; a target
//              the encoder refuses with LIMIT_EXCEEDED is a status row),
//              then vqtex_decode_volume;
//   av1+synth  for each vqtex row, every example frame coded as one AV1
//              sequence (encode_atlas_frames, speed 6) at the finest level
//              whose bitstream fits the vqtex file's bytes, decoded, then
//              vqtex_synthesize_volume as the ceiling.
// Encodes, decodes and syntheses run on 2 threads; the times are wall
// times in this process (av1+synth's encode: the whole level search;
// its decode: the AV1 decode and the synthesis).
// Measures: anim_stats.hpp's, every one of them per output frame against
// the example's frames. CSV: animation_rows.hpp. Summary: animation_summary.hpp.
// Pictures with --sheets: anim_pictures.hpp.
#pragma once

#include "bench_options.hpp"

namespace vqtex_tools {

int run_animation_protocol(const BenchOptions& o);

}  // namespace vqtex_tools
