// Pixel-level metrics: variety, seam_ratio, straight_seam_score.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "internal.hpp"

namespace vqtex_metrics {
namespace {

constexpr double kSeamSoftening = 0.25;  // grey levels
constexpr int kSeamNeighbours = 4;       // boundaries on each side for the baseline

inline int absdiff(uint8_t a, uint8_t b) { return std::abs(static_cast<int>(a) - static_cast<int>(b)); }

// Mean |I(x1, y) - I(x0, y)| over rows and RGB.
double column_step(const detail::Rgb8& im, int x0, int x1) {
  long long s = 0;
  for (int y = 0; y < im.h; ++y) {
    const uint8_t* row = &im.v[static_cast<size_t>(y) * im.w * 3];
    for (int c = 0; c < 3; ++c) s += absdiff(row[x0 * 3 + c], row[x1 * 3 + c]);
  }
  return static_cast<double>(s) / (3.0 * im.h);
}

// Mean |I(x, y1) - I(x, y0)| over columns and RGB.
double row_step(const detail::Rgb8& im, int y0, int y1) {
  const uint8_t* r0 = &im.v[static_cast<size_t>(y0) * im.w * 3];
  const uint8_t* r1 = &im.v[static_cast<size_t>(y1) * im.w * 3];
  long long s = 0;
  for (int j = 0; j < im.w * 3; ++j) s += absdiff(r0[j], r1[j]);
  return static_cast<double>(s) / (3.0 * im.w);
}

// d[k] = mean step across boundary k (between k and k+1); with wrap, the
// last entry is the boundary between the last and the first line.
std::vector<double> boundary_steps(const detail::Rgb8& im, bool vertical, bool wrap) {
  const int n = vertical ? im.w : im.h;
  const int count = wrap ? n : n - 1;
  std::vector<double> d(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) {
    const int a = k, b = (k + 1) % n;
    d[static_cast<size_t>(k)] = vertical ? column_step(im, a, b) : row_step(im, a, b);
  }
  return d;
}

void strongest_in(const std::vector<double>& d, bool wrap, bool vertical, SeamLine& best) {
  const int n = static_cast<int>(d.size());
  std::vector<double> nb;
  for (int k = 0; k < n; ++k) {
    nb.clear();
    for (int o = 1; o <= kSeamNeighbours; ++o) {
      for (int j : {k - o, k + o}) {
        if (wrap) {
          j = ((j % n) + n) % n;
          if (j == k) continue;
        } else if (j < 0 || j >= n) {
          continue;
        }
        nb.push_back(d[static_cast<size_t>(j)]);
      }
    }
    if (nb.empty()) continue;
    // Median (mean of the two middle values for an even count).
    std::sort(nb.begin(), nb.end());
    const size_t m = nb.size();
    const double med = m % 2 ? nb[m / 2] : 0.5 * (nb[m / 2 - 1] + nb[m / 2]);
    const double ratio = (d[static_cast<size_t>(k)] + kSeamSoftening) / (med + kSeamSoftening);
    if (ratio > best.ratio) {
      best.ratio = ratio;
      best.vertical = vertical;
      best.position = k;
    }
  }
}

}  // namespace

double variety(const Image& a, const Image& b) {
  const detail::Rgb8 ra = detail::to_rgb8(a, "first image");
  const detail::Rgb8 rb = detail::to_rgb8(b, "second image");
  if (ra.w != rb.w || ra.h != rb.h)
    throw std::invalid_argument("vqtex_metrics: variety needs two images of the same size");
  long long s = 0;
  for (size_t i = 0; i < ra.v.size(); ++i) s += absdiff(ra.v[i], rb.v[i]);
  return static_cast<double>(s) / (255.0 * static_cast<double>(ra.v.size()));
}

double seam_ratio(const Image& image) {
  const detail::Rgb8 im = detail::to_rgb8(image, "image");
  if (im.w < 2 || im.h < 2) throw std::invalid_argument("vqtex_metrics: seam_ratio needs at least 2x2 pixels");
  // Each direction weighs one half, whatever the aspect ratio, so that a
  // seamless but anisotropic texture (e.g. vertical planks) gives 1.
  const double seam = 0.5 * (column_step(im, im.w - 1, 0) + row_step(im, im.h - 1, 0));
  double cols = 0.0, rows = 0.0;
  for (int x = 0; x + 1 < im.w; ++x) cols += column_step(im, x, x + 1);
  for (int y = 0; y + 1 < im.h; ++y) rows += row_step(im, y, y + 1);
  const double inner = 0.5 * (cols / (im.w - 1) + rows / (im.h - 1));
  if (inner <= 0.0) return seam <= 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return seam / inner;
}

SeamLine strongest_straight_seam(const Image& image, bool include_wrap) {
  const detail::Rgb8 im = detail::to_rgb8(image, "image");
  SeamLine best;
  best.ratio = 0.0;
  if (im.w >= 3) strongest_in(boundary_steps(im, true, include_wrap), include_wrap, true, best);
  if (im.h >= 3) strongest_in(boundary_steps(im, false, include_wrap), include_wrap, false, best);
  if (best.ratio == 0.0) best = SeamLine{};
  return best;
}

double straight_seam_score(const Image& image, bool include_wrap) {
  return strongest_straight_seam(image, include_wrap).ratio;
}

}  // namespace vqtex_metrics
