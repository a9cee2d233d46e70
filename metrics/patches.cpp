// Nearest-neighbour patch metrics: coherence, completeness, copy_stats.
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "internal.hpp"

namespace vqtex_metrics {
namespace detail {
namespace {

// Slack added to the pruning limit: the float lower bound may exceed the
// exact integer SSD by rounding (worst case about 0.5*sqrt(SSD) for 7x7x3
// patches of 8-bit values), so prune only beyond best + slack.
inline double prune_limit(long long best) {
  if (best == LLONG_MAX) return std::numeric_limits<double>::infinity();
  const double b = static_cast<double>(best);
  return b + 0.5 * std::sqrt(b) + 1e-3 * b + 1.0;
}

void require_fits(const Rgb8& im, int p, const char* what) {
  if (im.w < p || im.h < p)
    throw std::invalid_argument(std::string("vqtex_metrics: ") + what + " is smaller than the patch size");
}

}  // namespace

PatchIndex::PatchIndex(const Rgb8& img, int patch) : img_(img), p_(patch) {
  if (patch < 1) throw std::invalid_argument("vqtex_metrics: patch must be >= 1");
  require_fits(img, patch, "image");
  const int dims = p_ * p_ * 3;

  // Orthonormal colour-opponent transform (rows) x 1-D orthonormal DCT-II.
  const double inv3 = 1.0 / std::sqrt(3.0), inv2 = 1.0 / std::sqrt(2.0), inv6 = 1.0 / std::sqrt(6.0);
  const double colour[3][3] = {{inv3, inv3, inv3}, {inv2, 0.0, -inv2}, {inv6, -2.0 * inv6, inv6}};
  auto dct = [&](int u, int x) {
    const double alpha = u == 0 ? std::sqrt(1.0 / p_) : std::sqrt(2.0 / p_);
    return alpha * std::cos(std::numbers::pi * (2.0 * x + 1.0) * u / (2.0 * p_));
  };
  // Feature 0 is the luminance DC (the sort key). Frequencies that do not
  // exist for tiny patches leave a zero basis vector, which only weakens the
  // bound.
  struct Term {
    int colour, u, v;
  };
  static constexpr Term kTerms[kFeatures] = {
      {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2},
      {1, 1, 0}, {1, 0, 1}, {2, 1, 0}, {2, 0, 1}, {0, 3, 0}, {0, 2, 1}, {0, 1, 2}, {0, 0, 3}};
  basis_.assign(static_cast<size_t>(dims) * kFeatures, 0.0);  // dims x features
  for (int k = 0; k < kFeatures; ++k) {
    const Term t = kTerms[k];
    if (t.u >= p_ || t.v >= p_) continue;
    for (int y = 0; y < p_; ++y)
      for (int x = 0; x < p_; ++x)
        for (int c = 0; c < 3; ++c)
          basis_[static_cast<size_t>((y * p_ + x) * 3 + c) * kFeatures + k] =
              colour[t.colour][c] * dct(t.u, x) * dct(t.v, y);
  }

  // Window grid: stride 1 unless that gives more than kMaxWindows windows.
  const int nx0 = img.w - p_ + 1, ny0 = img.h - p_ + 1;
  int stride = 1;
  auto count = [&](int s) {
    return static_cast<long long>((nx0 + s - 1) / s) * static_cast<long long>((ny0 + s - 1) / s);
  };
  while (count(stride) > kMaxWindows) ++stride;
  const int n = static_cast<int>(count(stride));

  std::vector<float> feat(static_cast<size_t>(n) * kFeatures);
  std::vector<int> pos(static_cast<size_t>(n));
  int i = 0;
  for (int y = 0; y < ny0; y += stride)
    for (int x = 0; x < nx0; x += stride, ++i) {
      features(img, x, y, &feat[static_cast<size_t>(i) * kFeatures]);
      pos[static_cast<size_t>(i)] = y * img.w + x;
    }

  std::vector<int> order(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) order[static_cast<size_t>(j)] = j;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const float fa = feat[static_cast<size_t>(a) * kFeatures], fb = feat[static_cast<size_t>(b) * kFeatures];
    return fa < fb || (fa == fb && a < b);
  });
  feat_.resize(feat.size());
  pos_.resize(pos.size());
  for (int j = 0; j < n; ++j) {
    const int src = order[static_cast<size_t>(j)];
    std::copy_n(&feat[static_cast<size_t>(src) * kFeatures], kFeatures, &feat_[static_cast<size_t>(j) * kFeatures]);
    pos_[static_cast<size_t>(j)] = pos[static_cast<size_t>(src)];
  }
}

// Not inlined so that queries and windows go through identical code: the
// same bytes always give bit-identical coordinates.
__attribute__((noinline)) void PatchIndex::features(const Rgb8& im, int x0, int y0, float* out) const {
  double acc[kFeatures] = {};
  const int row_len = 3 * p_;
  for (int y = 0; y < p_; ++y) {
    const uint8_t* row = &im.v[(static_cast<size_t>(y0 + y) * im.w + x0) * 3];
    const double* b = &basis_[static_cast<size_t>(y * row_len) * kFeatures];
    for (int j = 0; j < row_len; ++j) {
      const double v = row[j];
      const double* bj = b + static_cast<size_t>(j) * kFeatures;
      for (int k = 0; k < kFeatures; ++k) acc[k] += v * bj[k];
    }
  }
  for (int k = 0; k < kFeatures; ++k) out[k] = static_cast<float>(acc[k]);
}

long long PatchIndex::ssd(const uint8_t* q, int x0, int y0, long long bound) const {
  const int row_len = 3 * p_;
  long long total = 0;
  for (int y = 0; y < p_; ++y) {
    const uint8_t* row = &img_.v[(static_cast<size_t>(y0 + y) * img_.w + x0) * 3];
    const uint8_t* qr = q + y * row_len;
    int s = 0;
    for (int j = 0; j < row_len; ++j) {
      const int d = static_cast<int>(qr[j]) - static_cast<int>(row[j]);
      s += d * d;
    }
    total += s;
    if (total >= bound) return total;
  }
  return total;
}

PatchIndex::Match PatchIndex::nearest(const Rgb8& query, int qx, int qy, int hint_x, int hint_y) const {
  const int row_len = 3 * p_;
  uint8_t qbuf[3 * 64 * 64];
  std::vector<uint8_t> big;
  uint8_t* q = qbuf;
  if (p_ > 64) {
    big.resize(static_cast<size_t>(row_len) * p_);
    q = big.data();
  }
  for (int y = 0; y < p_; ++y)
    std::copy_n(&query.v[(static_cast<size_t>(qy + y) * query.w + qx) * 3], row_len, q + y * row_len);
  float qf[kFeatures];
  features(query, qx, qy, qf);

  Match best;
  long long best_ssd = LLONG_MAX;
  if (hint_x >= 0 && hint_y >= 0 && hint_x <= img_.w - p_ && hint_y <= img_.h - p_) {
    best_ssd = ssd(q, hint_x, hint_y, LLONG_MAX);
    best.x = hint_x;
    best.y = hint_y;
  }

  const int n = static_cast<int>(pos_.size());
  // First window whose key is >= the query's.
  int lo = 0, hi = n;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (feat_[static_cast<size_t>(mid) * kFeatures] < qf[0]) lo = mid + 1;
    else hi = mid;
  }
  int right = lo, left = lo - 1;
  double limit = prune_limit(best_ssd);
  const double inf = std::numeric_limits<double>::infinity();
  while (right < n || left >= 0) {
    const double dr = right < n ? static_cast<double>(feat_[static_cast<size_t>(right) * kFeatures]) - qf[0] : inf;
    const double dl = left >= 0 ? qf[0] - static_cast<double>(feat_[static_cast<size_t>(left) * kFeatures]) : inf;
    int i;
    double d;
    if (dr <= dl) {
      i = right++;
      d = dr;
    } else {
      i = left--;
      d = dl;
    }
    // Keys are sorted and we always take the closer side: once the closer
    // key alone exceeds the limit, every remaining window does too.
    if (d * d > limit) break;
    const float* f = &feat_[static_cast<size_t>(i) * kFeatures];
    float s0 = 0.f, s1 = 0.f, s2 = 0.f, s3 = 0.f;
    for (int k = 0; k < kFeatures; k += 4) {
      const float e0 = f[k] - qf[k], e1 = f[k + 1] - qf[k + 1], e2 = f[k + 2] - qf[k + 2], e3 = f[k + 3] - qf[k + 3];
      s0 += e0 * e0;
      s1 += e1 * e1;
      s2 += e2 * e2;
      s3 += e3 * e3;
    }
    if (static_cast<double>((s0 + s1) + (s2 + s3)) > limit) continue;
    const int pidx = pos_[static_cast<size_t>(i)];
    const int x = pidx % img_.w, y = pidx / img_.w;
    const long long s = ssd(q, x, y, best_ssd);
    if (s < best_ssd) {
      best_ssd = s;
      best.x = x;
      best.y = y;
      limit = prune_limit(best_ssd);
    }
  }
  best.ssd = best_ssd;
  return best;
}

double mean_nn_rms(const Rgb8& query, const PatchIndex& index, int max_queries, uint64_t seed) {
  const int p = index.patch();
  require_fits(query, p, "query image");
  if (max_queries < 1) throw std::invalid_argument("vqtex_metrics: max_queries must be >= 1");
  const int nx = query.w - p + 1, ny = query.h - p + 1;
  SplitMix64 rng(seed);
  const std::vector<int> idx = sample_indices(nx * ny, max_queries, rng);
  const double dims = index.dims();
  double sum = 0.0;
  for (int id : idx) {
    const PatchIndex::Match m = index.nearest(query, id % nx, id / nx);
    sum += std::sqrt(static_cast<double>(m.ssd) / dims);
  }
  return sum / static_cast<double>(idx.size());
}

CopyStats copy_stats_indexed(const Rgb8& output, const PatchIndex& index, int step, int max_queries,
                             uint64_t seed) {
  const int p = index.patch();
  require_fits(output, p, "output image");
  if (step < 1) throw std::invalid_argument("vqtex_metrics: step must be >= 1");
  if (max_queries < 1) throw std::invalid_argument("vqtex_metrics: max_queries must be >= 1");
  const int gx = (output.w - p) / step + 1, gy = (output.h - p) / step + 1;
  const long long dims = index.dims();
  std::vector<PatchIndex::Match> memo(static_cast<size_t>(gx) * static_cast<size_t>(gy));

  auto match = [&](int i, int j, int hx, int hy) -> const PatchIndex::Match& {
    PatchIndex::Match& m = memo[static_cast<size_t>(j) * gx + i];
    if (m.ssd < 0) m = index.nearest(output, i * step, j * step, hx, hy);
    return m;
  };
  long long pairs = 0, coherent = 0;
  auto pair = [&](const PatchIndex::Match& a, const PatchIndex::Match& b, int dx, int dy) {
    ++pairs;
    if (b.x - a.x == dx && b.y - a.y == dy) ++coherent;
  };

  if (static_cast<long long>(gx) * gy <= max_queries) {
    // Every grid point, in raster order; the left (else upper) neighbour's
    // match shifted by one step is tried first.
    for (int j = 0; j < gy; ++j)
      for (int i = 0; i < gx; ++i) {
        int hx = -1, hy = -1;
        if (i > 0) {
          const auto& l = memo[static_cast<size_t>(j) * gx + i - 1];
          hx = l.x + step;
          hy = l.y;
        } else if (j > 0) {
          const auto& u = memo[static_cast<size_t>(j - 1) * gx + i];
          hx = u.x;
          hy = u.y + step;
        }
        const PatchIndex::Match& m = match(i, j, hx, hy);
        if (i > 0) pair(memo[static_cast<size_t>(j) * gx + i - 1], m, step, 0);
        if (j > 0) pair(memo[static_cast<size_t>(j - 1) * gx + i], m, 0, step);
      }
  } else {
    // Seeded anchors, each with its right and lower neighbour.
    SplitMix64 rng(seed);
    const std::vector<int> anchors = sample_indices(gx * gy, std::max(1, max_queries / 3), rng);
    for (int a : anchors) {
      const int i = a % gx, j = a / gx;
      const PatchIndex::Match m = match(i, j, -1, -1);
      if (i + 1 < gx) pair(m, match(i + 1, j, m.x + step, m.y), step, 0);
      if (j + 1 < gy) pair(m, match(i, j + 1, m.x, m.y + step), 0, step);
    }
  }

  CopyStats st;
  long long sampled = 0, exact = 0;
  double rms = 0.0;
  for (const auto& m : memo) {
    if (m.ssd < 0) continue;
    ++sampled;
    if (4 * m.ssd < dims) ++exact;  // RMS < 0.5
    rms += std::sqrt(static_cast<double>(m.ssd) / static_cast<double>(dims));
  }
  st.patches = static_cast<int>(sampled);
  st.pairs = static_cast<int>(pairs);
  st.exact_share = sampled ? static_cast<double>(exact) / static_cast<double>(sampled) : 0.0;
  st.mean_rms = sampled ? rms / static_cast<double>(sampled) : 0.0;
  st.neighbour_coherence = pairs ? static_cast<double>(coherent) / static_cast<double>(pairs) : 0.0;
  return st;
}

}  // namespace detail

double coherence(const Image& output, const Image& exemplar, int patch, int max_queries, uint64_t seed) {
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  const detail::PatchIndex index(ex, patch);
  return detail::mean_nn_rms(out, index, max_queries, detail::derive_seed(seed, 4000));
}

double completeness(const Image& reference, const Image& output, int patch, int max_queries, uint64_t seed) {
  const detail::Rgb8 ref = detail::to_rgb8(reference, "reference");
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::PatchIndex index(out, patch);
  return detail::mean_nn_rms(ref, index, max_queries, detail::derive_seed(seed, 4001));
}

CopyStats copy_stats(const Image& output, const Image& exemplar, int patch, int step, int max_queries,
                     uint64_t seed) {
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  const detail::PatchIndex index(ex, patch);
  return detail::copy_stats_indexed(out, index, step, max_queries, detail::derive_seed(seed, 4002));
}

}  // namespace vqtex_metrics
