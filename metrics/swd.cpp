// Sliced Wasserstein distance between mean-removed patch distributions.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "internal.hpp"

namespace vqtex_metrics {
namespace {

using detail::Rgb8;
using detail::SplitMix64;

struct FloatRgb {
  int w = 0, h = 0;
  std::vector<float> v;  // w*h*3
};

// Mirror an index into [0, n) without repeating the edge sample.
inline int mirror(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
  return i;
}

// Binomial [1 4 6 4 1]/16 blur, keeping pixels at even coordinates. The
// finest level is read as the bytes it is (each converts to the same float
// it would have been), so a large image is never held as floats whole.
template <typename Levels>
FloatRgb reduce(const Levels& in) {
  static constexpr float k[5] = {1.f / 16, 4.f / 16, 6.f / 16, 4.f / 16, 1.f / 16};
  const int w2 = (in.w + 1) / 2, h2 = (in.h + 1) / 2;
  std::vector<float> tmp(static_cast<size_t>(w2) * static_cast<size_t>(in.h) * 3);
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < w2; ++x)
      for (int c = 0; c < 3; ++c) {
        float s = 0.f;
        for (int t = -2; t <= 2; ++t)
          s += k[t + 2] * in.v[(static_cast<size_t>(y) * in.w + mirror(2 * x + t, in.w)) * 3 + c];
        tmp[(static_cast<size_t>(y) * w2 + x) * 3 + c] = s;
      }
  FloatRgb out;
  out.w = w2;
  out.h = h2;
  out.v.resize(static_cast<size_t>(w2) * static_cast<size_t>(h2) * 3);
  for (int y = 0; y < h2; ++y)
    for (int x = 0; x < w2; ++x)
      for (int c = 0; c < 3; ++c) {
        float s = 0.f;
        for (int t = -2; t <= 2; ++t)
          s += k[t + 2] * tmp[(static_cast<size_t>(mirror(2 * y + t, in.h)) * w2 + x) * 3 + c];
        out.v[(static_cast<size_t>(y) * w2 + x) * 3 + c] = s;
      }
  return out;
}

// Mean-removed patch vectors (n x dims) at seeded positions.
template <typename Levels>
std::vector<float> patch_vectors(const Levels& im, int p, int max_patches, uint64_t seed, int* n_out) {
  const int nx = im.w - p + 1, ny = im.h - p + 1;
  SplitMix64 rng(seed);
  const std::vector<int> idx = detail::sample_indices(nx * ny, max_patches, rng);
  const int dims = p * p * 3;
  std::vector<float> out(idx.size() * static_cast<size_t>(dims));
  for (size_t i = 0; i < idx.size(); ++i) {
    const int x0 = idx[i] % nx, y0 = idx[i] / nx;
    float* dst = &out[i * static_cast<size_t>(dims)];
    double mean[3] = {0, 0, 0};
    for (int y = 0; y < p; ++y) {
      const auto* row = &im.v[(static_cast<size_t>(y0 + y) * im.w + x0) * 3];
      for (int j = 0; j < 3 * p; ++j) {
        dst[y * 3 * p + j] = row[j];
        mean[j % 3] += row[j];
      }
    }
    const float m[3] = {static_cast<float>(mean[0] / (p * p)), static_cast<float>(mean[1] / (p * p)),
                        static_cast<float>(mean[2] / (p * p))};
    for (int j = 0; j < dims; ++j) dst[j] -= m[j % 3];
  }
  *n_out = static_cast<int>(idx.size());
  return out;
}

// proj[d * n + i] = <patch i, direction d>. dirs_t is dims x ndirs (the
// transposed direction matrix); directions are processed 16 at a time in
// four 4-float registers (GCC vector extension), the rest one by one.
std::vector<float> project(const std::vector<float>& vecs, int n, const std::vector<float>& dirs_t,
                           int ndirs, int dims) {
  using v4 = float __attribute__((vector_size(16)));
  std::vector<float> proj(static_cast<size_t>(ndirs) * static_cast<size_t>(n));
  int d0 = 0;
  for (; d0 + 16 <= ndirs; d0 += 16) {
    for (int i = 0; i < n; ++i) {
      const float* v = &vecs[static_cast<size_t>(i) * dims];
      v4 acc[4] = {};
      for (int j = 0; j < dims; ++j) {
        const float* u = &dirs_t[static_cast<size_t>(j) * ndirs + d0];
        const v4 vj = {v[j], v[j], v[j], v[j]};
        for (int k = 0; k < 4; ++k) {
          v4 uk;
          std::memcpy(&uk, u + 4 * k, sizeof uk);
          acc[k] += vj * uk;
        }
      }
      float out[16];
      std::memcpy(out, acc, sizeof out);
      for (int k = 0; k < 16; ++k) proj[static_cast<size_t>(d0 + k) * n + i] = out[k];
    }
  }
  for (; d0 < ndirs; ++d0)
    for (int i = 0; i < n; ++i) {
      const float* v = &vecs[static_cast<size_t>(i) * dims];
      float s = 0.f;
      for (int j = 0; j < dims; ++j) s += v[j] * dirs_t[static_cast<size_t>(j) * ndirs + d0];
      proj[static_cast<size_t>(d0) * n + i] = s;
    }
  return proj;
}

}  // namespace

SwdResult sliced_wasserstein(const Image& a, const Image& b, int levels, int patch, int projections,
                             uint64_t seed, int max_patches) {
  if (max_patches < 1) throw std::invalid_argument("vqtex_metrics: max_patches must be >= 1");
  if (levels < 1) throw std::invalid_argument("vqtex_metrics: levels must be >= 1");
  if (patch < 1) throw std::invalid_argument("vqtex_metrics: patch must be >= 1");
  if (projections < 1) throw std::invalid_argument("vqtex_metrics: projections must be >= 1");
  const Rgb8 ra = detail::to_rgb8(a, "first image");
  const Rgb8 rb = detail::to_rgb8(b, "second image");
  if (std::min({ra.w, ra.h, rb.w, rb.h}) < patch)
    throw std::invalid_argument("vqtex_metrics: image smaller than the SWD patch size");
  const int dims = patch * patch * 3;
  SwdResult res;
  FloatRgb fa, fb;  // the level below the finest, and so on
  for (int level = 0; level < levels; ++level) {
    if (level == 1) {
      fa = reduce(ra);
      fb = reduce(rb);
    } else if (level > 1) {
      fa = reduce(fa);
      fb = reduce(fb);
    }
    const int aw = level ? fa.w : ra.w, ah = level ? fa.h : ra.h, bw = level ? fb.w : rb.w, bh = level ? fb.h : rb.h;
    if (std::min({aw, ah, bw, bh}) < patch) break;

    // Random unit directions, the same for both images.
    SplitMix64 drng(detail::derive_seed(seed, 1000 + static_cast<uint64_t>(level)));
    std::vector<float> dirs_t(static_cast<size_t>(projections) * dims);
    for (int d = 0; d < projections; ++d) {
      double norm = 0.0;
      std::vector<double> g(static_cast<size_t>(dims));
      do {
        norm = 0.0;
        for (double& x : g) {
          x = drng.gaussian();
          norm += x * x;
        }
      } while (norm < 1e-12);
      norm = std::sqrt(norm);
      for (int j = 0; j < dims; ++j) dirs_t[static_cast<size_t>(j) * projections + d] = static_cast<float>(g[j] / norm);
    }

    // The same position seed for both images: identical images give 0.
    const uint64_t pseed = detail::derive_seed(seed, 2000 + static_cast<uint64_t>(level));
    int na = 0, nb = 0;
    const std::vector<float> va =
        level ? patch_vectors(fa, patch, max_patches, pseed, &na) : patch_vectors(ra, patch, max_patches, pseed, &na);
    const std::vector<float> vb =
        level ? patch_vectors(fb, patch, max_patches, pseed, &nb) : patch_vectors(rb, patch, max_patches, pseed, &nb);
    const std::vector<float> pa = project(va, na, dirs_t, projections, dims);
    const std::vector<float> pb = project(vb, nb, dirs_t, projections, dims);

    double sum = 0.0;
    long long count = 0;
    for (int d = 0; d < projections; ++d) {
      std::vector<float> sa(pa.begin() + static_cast<long>(d) * na, pa.begin() + static_cast<long>(d + 1) * na);
      std::vector<float> sb(pb.begin() + static_cast<long>(d) * nb, pb.begin() + static_cast<long>(d + 1) * nb);
      long long n = 0;
      sum += detail::sorted_quantile_sq_diff(sa, sb, &n);
      count += n;
    }
    res.per_level.push_back(count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0);
  }
  double s = 0.0;
  for (double v : res.per_level) s += v;
  res.mean = res.per_level.empty() ? 0.0 : s / static_cast<double>(res.per_level.size());
  return res;
}

}  // namespace vqtex_metrics
