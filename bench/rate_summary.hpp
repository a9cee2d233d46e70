// The first table of vqtex-bench's printed summary: the mean over textures
// of each codec's bytes and main scores, per protocol and rate point (the
// synth protocol has a summary of its own).
#pragma once

#include <vector>

#include "bench_rows.hpp"

namespace vqtex_tools {

// `header`: print the column titles (when a codec protocol was run).
void print_rate_summary(const std::vector<Row>& rows, bool header);

}  // namespace vqtex_tools
