// cli_common.hpp - helpers shared by the command-line programs: parsing of
// sizes, shape lists and codeword lists, a terminal progress bar (JSON output is in batch.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

// "512x256" or "512" (square). Throws std::invalid_argument.
void parse_size(const std::string& text, uint32_t& width, uint32_t& height);

// "9x9:2,7x7:2,5x5:2,3x3:1", finest level first, into `shapes`.
void parse_shapes(const std::string& text, vqtex_shape (&shapes)[VQTEX_MAX_LEVELS]);

// "512" (every level), "512,256,128,64" (finest first) or "0.1" (a fraction
// of each level's training vectors).
void parse_codewords(const std::string& text, vqtex_tsvq_params& params);

// Progress callback drawing a bar on stderr when it is a terminal and the
// work has taken longer than a second; silent otherwise.
struct ProgressBar {
    explicit ProgressBar(bool enabled);
    ~ProgressBar();
    static int callback(void* user, vqtex_stage stage, uint64_t done, uint64_t total);
    void finish();

    bool enabled;
    double started;
    bool drawn = false;
};

double now_seconds();

}  // namespace vqtex_tools
