// score_all / floor_scores: every metric with one set of derived seeds.
#include "internal.hpp"

namespace vqtex_metrics {
namespace {

// Seed tags: each metric gets its own stream, identical between score_all
// and floor_scores so that the two are directly comparable.
constexpr uint64_t kTagSwd = 1, kTagColour = 2, kTagCoherence = 3, kTagCompleteness = 4, kTagCopy = 5;

}  // namespace

Scores score_all(const Image& output, const Image& reference_heldout, const Image& exemplar, uint64_t seed) {
  Scores s;
  s.swd = sliced_wasserstein(output, reference_heldout, 4, 7, 64, detail::derive_seed(seed, kTagSwd));
  s.colour = colour_distance(output, reference_heldout, detail::derive_seed(seed, kTagColour));
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::Rgb8 ref = detail::to_rgb8(reference_heldout, "reference");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  {
    // One exemplar index serves coherence and copy_stats.
    const detail::PatchIndex ex_index(ex, 7);
    s.coherence = detail::mean_nn_rms(out, ex_index, 256, detail::derive_seed(seed, kTagCoherence));
    s.copy = detail::copy_stats_indexed(out, ex_index, 8, 384, detail::derive_seed(seed, kTagCopy));
  }
  {
    const detail::PatchIndex out_index(out, 7);
    s.completeness = detail::mean_nn_rms(ref, out_index, 256, detail::derive_seed(seed, kTagCompleteness));
  }
  s.seam_ratio = seam_ratio(output);
  s.straight_seam = straight_seam_score(output, true);
  return s;
}

Scores floor_scores(const Image& reference_heldout, const Image& exemplar, uint64_t seed) {
  Scores s;
  // Output := exemplar for the metrics against the reference.
  s.swd = sliced_wasserstein(exemplar, reference_heldout, 4, 7, 64, detail::derive_seed(seed, kTagSwd));
  s.colour = colour_distance(exemplar, reference_heldout, detail::derive_seed(seed, kTagColour));
  const detail::Rgb8 ref = detail::to_rgb8(reference_heldout, "reference");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  {
    const detail::PatchIndex ex_index(ex, 7);
    s.completeness = detail::mean_nn_rms(ref, ex_index, 256, detail::derive_seed(seed, kTagCompleteness));
    // Output := reference for the metrics against the exemplar.
    s.coherence = detail::mean_nn_rms(ref, ex_index, 256, detail::derive_seed(seed, kTagCoherence));
    s.copy = detail::copy_stats_indexed(ref, ex_index, 8, 384, detail::derive_seed(seed, kTagCopy));
  }
  s.seam_ratio = 1.0;
  s.straight_seam = straight_seam_score(exemplar, false);
  return s;
}

}  // namespace vqtex_metrics
