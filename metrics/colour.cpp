// CIE L*a*b* colour statistics.
#include <array>
#include <cmath>

#include "internal.hpp"

namespace vqtex_metrics {
namespace {

constexpr int kMaxColourSamples = 65536;
constexpr int kRandomDirections = 7;

// sRGB transfer function (IEC 61966-2-1), 8-bit code -> linear [0,1].
const std::array<double, 256>& linear_table() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[static_cast<size_t>(i)] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    }
    return t;
  }();
  return table;
}

// CIE f(t) for L*a*b*: cube root above (6/29)^3, linear segment below.
inline double lab_f(double t) {
  constexpr double d = 6.0 / 29.0;
  return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

}  // namespace

void srgb_to_lab(uint8_t r8, uint8_t g8, uint8_t b8, double lab[3]) {
  const auto& lin = linear_table();
  const double r = lin[r8], g = lin[g8], b = lin[b8];
  // Linear sRGB -> XYZ, D65 (IEC 61966-2-1 matrix).
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  // D65 reference white (Y = 1).
  constexpr double xn = 0.95047, yn = 1.0, zn = 1.08883;
  const double fx = lab_f(x / xn), fy = lab_f(y / yn), fz = lab_f(z / zn);
  lab[0] = 116.0 * fy - 16.0;
  lab[1] = 500.0 * (fx - fy);
  lab[2] = 200.0 * (fy - fz);
}

namespace {

struct LabPixels {
  std::vector<float> l, a, b;  // sampled pixels
  double mean[3] = {0, 0, 0};  // over all pixels
};

LabPixels lab_pixels(const detail::Rgb8& im, uint64_t seed) {
  const int n = im.w * im.h;
  LabPixels out;
  // Sample for the distribution; the mean uses every pixel.
  detail::SplitMix64 rng(seed);
  const std::vector<int> idx = detail::sample_indices(n, kMaxColourSamples, rng);
  out.l.reserve(idx.size());
  out.a.reserve(idx.size());
  out.b.reserve(idx.size());
  size_t next = 0;
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    double lab[3];
    const uint8_t* p = &im.v[static_cast<size_t>(i) * 3];
    srgb_to_lab(p[0], p[1], p[2], lab);
    for (int c = 0; c < 3; ++c) sum[c] += lab[c];
    if (next < idx.size() && idx[next] == i) {
      out.l.push_back(static_cast<float>(lab[0]));
      out.a.push_back(static_cast<float>(lab[1]));
      out.b.push_back(static_cast<float>(lab[2]));
      ++next;
    }
  }
  for (int c = 0; c < 3; ++c) out.mean[c] = sum[c] / n;
  return out;
}

std::vector<float> along(const LabPixels& p, const double dir[3]) {
  std::vector<float> v(p.l.size());
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = static_cast<float>(dir[0] * p.l[i] + dir[1] * p.a[i] + dir[2] * p.b[i]);
  return v;
}

}  // namespace

ColourDistance colour_distance(const Image& a, const Image& b, uint64_t seed) {
  const detail::Rgb8 ra = detail::to_rgb8(a, "first image");
  const detail::Rgb8 rb = detail::to_rgb8(b, "second image");
  // Same sampling seed for both: identical images give exactly 0.
  const uint64_t sseed = detail::derive_seed(seed, 3000);
  const LabPixels la = lab_pixels(ra, sseed);
  const LabPixels lb = lab_pixels(rb, sseed);

  ColourDistance res;
  double d2 = 0.0;
  for (int c = 0; c < 3; ++c) d2 += (la.mean[c] - lb.mean[c]) * (la.mean[c] - lb.mean[c]);
  res.mean_delta_e = std::sqrt(d2);

  std::vector<std::array<double, 3>> dirs = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  detail::SplitMix64 drng(detail::derive_seed(seed, 3001));
  for (int k = 0; k < kRandomDirections; ++k) {
    std::array<double, 3> d{};
    double norm = 0.0;
    do {
      norm = 0.0;
      for (double& x : d) {
        x = drng.gaussian();
        norm += x * x;
      }
    } while (norm < 1e-12);
    norm = std::sqrt(norm);
    for (double& x : d) x /= norm;
    dirs.push_back(d);
  }
  double sum = 0.0;
  long long count = 0;
  for (const auto& d : dirs) {
    std::vector<float> pa = along(la, d.data());
    std::vector<float> pb = along(lb, d.data());
    long long n = 0;
    sum += detail::sorted_quantile_sq_diff(pa, pb, &n);
    count += n;
  }
  res.distribution = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  return res;
}

}  // namespace vqtex_metrics
