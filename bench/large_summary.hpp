// The large protocol's printed summary in vqtex-bench: vqtex against
// peer + synthesis and the acceptance test (docs/METRICS.md, "The
// summary").
#pragma once

#include <vector>

#include "bench_rows.hpp"

namespace vqtex_tools {

// The large protocol's summary, per rate point: the mean completeness, SWD
// and coherence of vqtex, of every PEER+synth and PEER+gmic row and of the
// ceilings; then vqtex against the best PEER+synth row, the project's
// acceptance test ("at every rate point, vqtex's mean completeness, SWD and
// coherence are at or below the best peer + vqtex synthesis row's, and at
// or below it on at least two thirds of the textures"), and, for
// reference, against the best PEER+gmic row.
//
// The best row per metric is the one with the lowest mean among the peers
// that fit the budget on every texture vqtex scored, so that its mean is
// taken over the same textures as vqtex's. A peer that misses some
// textures (typically the hardest ones, at the smallest budgets) would
// otherwise look better by leaving them out: it is not a candidate, but it
// is still compared with vqtex on the textures both scored, with n. When no
// peer covers every texture, the best is taken among those that cover the
// most, and the verdict says "partial".
void print_large_summary(const std::vector<Row>& rows);

}  // namespace vqtex_tools
