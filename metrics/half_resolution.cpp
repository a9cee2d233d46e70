// Coherence at half resolution: the patch coherence of section 3 of
// docs/METRICS.md on both images reduced 2x. A 7x7 window then covers a
// 14x14 area of the original, so the measure sees structure (a broken
// stone, a misaligned row of bricks) at twice the scale of the full-
// resolution coherence, and fine grain or noise, averaged away by the
// reduction, moves it less.
#include "internal.hpp"

namespace vqtex_metrics {
namespace detail {

Rgb8 half_resolution(const Rgb8& im) {
  // 2x2 box average with integer rounding (half up); an odd last row or
  // column is dropped. Integer arithmetic keeps the result bit-exact on
  // every machine.
  Rgb8 out;
  out.w = im.w / 2;
  out.h = im.h / 2;
  out.v.resize(static_cast<size_t>(out.w) * out.h * 3);
  for (int y = 0; y < out.h; ++y) {
    const uint8_t* r0 = &im.v[static_cast<size_t>(2 * y) * im.w * 3];
    const uint8_t* r1 = r0 + static_cast<size_t>(im.w) * 3;
    uint8_t* dst = &out.v[static_cast<size_t>(y) * out.w * 3];
    for (int x = 0; x < out.w; ++x)
      for (int c = 0; c < 3; ++c) {
        const int s = r0[6 * x + c] + r0[6 * x + 3 + c] + r1[6 * x + c] + r1[6 * x + 3 + c];
        dst[3 * x + c] = static_cast<uint8_t>((s + 2) >> 2);
      }
  }
  return out;
}

}  // namespace detail

double coherence_half_resolution(const Image& output, const Image& exemplar, int patch, int max_queries,
                                 uint64_t seed) {
  const detail::Rgb8 out = detail::half_resolution(detail::to_rgb8(output, "output"));
  const detail::Rgb8 ex = detail::half_resolution(detail::to_rgb8(exemplar, "exemplar"));
  const detail::PatchIndex index(ex, patch);
  return detail::mean_nn_rms(out, index, max_queries, detail::derive_seed(seed, 4003));
}

}  // namespace vqtex_metrics
