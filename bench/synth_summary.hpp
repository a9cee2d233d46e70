// The printed summary of vqtex-bench's synth protocol (docs/METRICS.md,
// "The synth protocol").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "bench_rows.hpp"

namespace vqtex_tools {

// The synth protocol's summary: the mean of every score per synthesiser
// over the textures it scored (column n; the floor over all of them), then
// one line per texture with the metrics on which vqtex scores worse than
// G'MIC, so that a developer sees which textures lose and how.
void print_synth_summary(const std::vector<Row>& rows, const std::map<std::string, AllScores>& floors);

}  // namespace vqtex_tools
