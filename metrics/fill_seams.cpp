// fill_seams.cpp - how visible the boundary of a filled region is (hole
// filling, paper section 5.1): differences across the boundary compared with
// differences inside the known part of the image.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "internal.hpp"
#include "metrics.hpp"

namespace vqtex_metrics {

FillSeamStats fill_seam_stats(const Image& filled, const std::vector<uint8_t>& mask) {
  const detail::Rgb8 rgb = detail::to_rgb8(filled, "filled image");
  const int w = rgb.w, h = rgb.h;
  if (mask.size() != std::size_t(w) * std::size_t(h))
    throw std::invalid_argument("fill_seam_stats: mask size does not match the image");
  const auto in = [&](int x, int y) { return mask[std::size_t(y) * w + x] != 0; };
  const auto d = [&](int x0, int y0, int x1, int y1) {
    const uint8_t* a = rgb.v.data() + (std::size_t(y0) * w + x0) * 3;
    const uint8_t* b = rgb.v.data() + (std::size_t(y1) * w + x1) * 3;
    return (std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2])) / 3.0;
  };
  // Axis 0: horizontal pairs, 1: vertical pairs.
  std::vector<double> known[2];
  struct Pair {
    int axis;
    bool trailing;
    double d;
  };
  std::vector<Pair> boundary;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int axis = 0; axis < 2; ++axis) {
        const int x1 = x + (axis == 0), y1 = y + (axis == 1);
        if (x1 >= w || y1 >= h) continue;
        const bool a = in(x, y), b = in(x1, y1);
        if (!a && !b) known[axis].push_back(d(x, y, x1, y1));
        // (x, y) is left of / above (x1, y1): trailing when the known pixel is the second.
        else if (a != b) boundary.push_back({axis, a, d(x, y, x1, y1)});
      }
  if (known[0].empty() || known[1].empty() || boundary.empty())
    throw std::invalid_argument("fill_seam_stats: the mask leaves no known pairs or no boundary");
  double mean[2], p95[2];
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double>& v = known[axis];
    double s = 0;
    for (double x : v) s += x;
    mean[axis] = std::max(s / double(v.size()), 1e-9);
    std::sort(v.begin(), v.end());
    p95[axis] = v[std::min(v.size() - 1, v.size() * 95 / 100)];
  }
  FillSeamStats r;
  double ratio[2] = {0, 0}, exceed[2] = {0, 0};
  int count[2] = {0, 0};
  for (const Pair& p : boundary) {
    const int k = p.trailing ? 1 : 0;
    ratio[k] += p.d / mean[p.axis];
    exceed[k] += p.d > p95[p.axis] ? 1 : 0;
    ++count[k];
  }
  const auto share = [](double s, int n) { return n ? s / n : 0.0; };
  r.pairs_leading = count[0];
  r.pairs_trailing = count[1];
  r.ratio_leading = share(ratio[0], count[0]);
  r.ratio_trailing = share(ratio[1], count[1]);
  r.ratio_all = share(ratio[0] + ratio[1], count[0] + count[1]);
  r.exceed_leading = share(exceed[0], count[0]);
  r.exceed_trailing = share(exceed[1], count[1]);
  r.exceed_all = share(exceed[0] + exceed[1], count[0] + count[1]);
  return r;
}

}  // namespace vqtex_metrics
