// Coherence at half resolution: the patch coherence of section 3 of
// docs/METRICS.md on both images reduced 2x. A 7x7 window then covers a
// 14x14 area of the original, so the measure sees structure (a broken
// stone, a misaligned row of bricks) at twice the scale of the full-
// resolution coherence, and fine grain or noise, averaged away by the
// reduction, moves it less.
//
// The exemplar is reduced at each of its four phases (the 2x2 boxes that
// start at even or odd columns and rows) and an output window's nearest is
// the nearest over all four: an output holds the example at any
// translation, and a copy at an odd one reduces to the exemplar's other
// phase. With only the even phase, the exemplar itself moved by one pixel
// scored 17-21 on stk_granite, worse than a held-out photograph (12.2).
#include <memory>
#include <vector>

#include "internal.hpp"

namespace vqtex_metrics {
namespace detail {

Rgb8 half_resolution(const Rgb8& im, int phase_x, int phase_y) {
  // 2x2 box average with integer rounding (half up); an odd last row or
  // column is dropped. Integer arithmetic keeps the result bit-exact on
  // every machine.
  Rgb8 out;
  out.w = (im.w - phase_x) / 2;
  out.h = (im.h - phase_y) / 2;
  out.v.resize(static_cast<size_t>(out.w) * out.h * 3);
  for (int y = 0; y < out.h; ++y) {
    const uint8_t* r0 = &im.v[(static_cast<size_t>(2 * y + phase_y) * im.w + static_cast<size_t>(phase_x)) * 3];
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
  const detail::Rgb8 out = detail::half_resolution(detail::to_rgb8(output, "output"), 0, 0);
  const detail::Rgb8 full = detail::to_rgb8(exemplar, "exemplar");
  detail::Rgb8 phases[4];
  std::vector<const detail::PatchIndex*> indexes;
  std::vector<std::unique_ptr<detail::PatchIndex>> held;
  for (int k = 0; k < 4; ++k) {
    phases[k] = detail::half_resolution(full, k & 1, k >> 1);
    // A phase too small for a window (an exemplar of 2 p - 1 pixels) adds
    // nothing; the even phase is checked by the index itself.
    if (k > 0 && (phases[k].w < patch || phases[k].h < patch)) continue;
    held.push_back(std::make_unique<detail::PatchIndex>(phases[k], patch));
    indexes.push_back(held.back().get());
  }
  return detail::mean_nn_rms(out, indexes, max_queries, detail::derive_seed(seed, 4003));
}

}  // namespace vqtex_metrics
