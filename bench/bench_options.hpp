// vqtex-bench's command line (docs/BENCHMARKS.md, "vqtex-bench").
#pragma once

#include <cstdint>
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

    bool want(const std::string& protocol) const;
    // The rate points (encodes, peers, ASTC) serve only the same and large
    // protocols.
    bool rates() const { return want("same") || want("large"); }
};

// Reads the command line into `o`. Returns -1 to go on, or the exit status
// when the parser has answered (--help, an invalid option).
int parse_options(int argc, char** argv, BenchOptions& o);

}  // namespace vqtex_tools
