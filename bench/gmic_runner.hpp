// G'MIC's syntexturize_matchpatch as vqtex-bench runs it (the synth
// protocol's gmic rows, the large protocol's PEER+gmic rows and ceiling):
// one thread, seeded with srand so that a run repeats, its outputs kept in
// a cache between runs (docs/METRICS.md, "The synth protocol").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "bench_images.hpp"

namespace vqtex_tools {

// G'MIC's syntexturize_matchpatch on the exemplar, or its cached output.
struct GmicResult {
    std::string status = "ok";  // ok, missing, failed
    Image output;
    double seconds = 0;  // the whole gmic command, wall time
    long peak_kib = 0;
    bool cached = false;
};

// The CSV setting of a row G'MIC made (without the cache mark).
std::string gmic_setting(uint64_t seed);

// G'MIC seeds its generator from the clock unless told; `srand` makes a run
// repeatable, which is what lets its outputs be cached by seed. A cache
// entry is NAME_WxH_sSEED_HASH.png plus a .txt holding the seconds and peak
// KiB of the run that made it, so cached rows still report G'MIC's cost.
// `available`: gmic is installed (otherwise the status is "missing").
GmicResult run_gmic(const Image& exemplar, int w, int h, uint64_t seed, const std::string& stem,
                    const std::filesystem::path& scratch, const std::string& cache, bool available);

}  // namespace vqtex_tools
