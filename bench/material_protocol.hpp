// vqtex-bench's materials protocol: material sets, several maps of one
// surface (albedo, normal, gloss) stored in one file and decoded aligned
// (vqtex_encode_maps, vqtex_decode_maps). Per set and rate point (the
// default quality, then the byte targets), every map is scored against its
// own example map, the pairs of maps by the correlation of their
// luminances against the example's, and the normal map by its shading;
// beside them the same maps each stored alone at the bytes the set gave it,
// which keeps their quality but loses their alignment (docs/METRICS.md,
// "The materials protocol").
#pragma once

#include "bench_options.hpp"

namespace vqtex_tools {

// Every set of o.folder (one folder of PNG maps each): the CSV, with
// --sheets the contact sheets, and the printed summary. Returns the exit
// status: 0, or 1 when a set does not load or an encode or decode failed
// (reported on stderr; a target too small for the maps is not a failure,
// its rows say no-fit).
int run_material_protocol(const BenchOptions& o);

}  // namespace vqtex_tools
