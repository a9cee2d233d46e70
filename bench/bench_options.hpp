// vqtex-bench's command line (docs/BENCHMARKS.md, "vqtex-bench").
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace vqtex_tools {

struct BenchOptions {
    std::string folder = "corpus", pattern = ".png", csv;
    std::vector<int> qualities{20, 50, 80};
    uint32_t limit = 0;
    uint64_t seed = 1;
    bool quick = false, no_peers = false, no_times = false;
    std::string sheets, synth_cache;
    std::vector<std::string> protocols{"same", "large"};
    uint32_t synth_size = 0;
    bool atlas = false;
    std::vector<uint64_t> target_sizes;
    // The materials protocol (material_protocol.hpp): the sets to run (all
    // when empty), the side the maps are reduced to (0: as they are) and
    // the decoded side (0: the maps' side after the reduction).
    std::vector<std::string> sets;
    uint32_t material_side = 0, material_output = 0;
    // The compact protocol: also synthesise from lossless parts of the
    // input (the ceiling of any atlas that is a part of it).
    bool compact_parts = false;
    // ... and from lossless compactions of it (inverse texture synthesis).
    bool compact_inverse = false;
    // The animation protocol: the folder of the shared corpus whose
    // photographs become animations (empty: none; default the source
    // tree's ../shared/corpus) and the output frame count.
    std::string shared;
    uint32_t anim_frames = 64;

    bool want(const std::string& protocol) const;
    // The rate points (encodes, peers, ASTC) serve only the same and large
    // protocols. The materials protocol runs alone: its folder holds sets
    // of maps, not photographs.
    bool rates() const { return want("same") || want("large"); }
};

// The folder's PNG files whose name contains the pattern, sorted, at most
// --limit of them; and the CSV file (null without --csv). False, with an
// error on stderr, when there is none or the CSV cannot be written.
bool list_inputs(const BenchOptions& o, std::vector<std::filesystem::path>& files, FILE*& csv);

// Reads the command line into `o`. Returns -1 to go on, or the exit status
// when the parser has answered (--help, an invalid option).
int parse_options(int argc, char** argv, BenchOptions& o);

}  // namespace vqtex_tools
