// Nearest-neighbour patch metrics: coherence, completeness, copy_stats.
#include <algorithm>
#include <climits>
#include <cstring>
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

PatchIndex::PatchIndex(const Rgb8& img, int patch, int max_windows) : img_(&img), p_(patch) {
  if (patch < 1 || patch > 64) throw std::invalid_argument("vqtex_metrics: patch must be in 1..64");
  if (max_windows < 1) throw std::invalid_argument("vqtex_metrics: max_windows must be >= 1");
  require_fits(img, patch, "image");
  dims_ = p_ * p_ * 3;
  padded_ = (dims_ + 15) / 16 * 16;
  w_ = img.w;

  // Orthonormal colour-opponent transform (rows) x 1-D orthonormal DCT-II.
  const double inv3 = 1.0 / std::sqrt(3.0), inv2 = 1.0 / std::sqrt(2.0), inv6 = 1.0 / std::sqrt(6.0);
  const double colour[3][3] = {{inv3, inv3, inv3}, {inv2, 0.0, -inv2}, {inv6, -2.0 * inv6, inv6}};
  auto dct = [&](int u, int x) {
    const double alpha = u == 0 ? std::sqrt(1.0 / p_) : std::sqrt(2.0 / p_);
    return alpha * std::cos(std::numbers::pi * (2.0 * x + 1.0) * u / (2.0 * p_));
  };
  // Frequencies that do not exist for tiny patches leave a zero basis
  // vector, which only weakens the bound.
  struct Term {
    int colour, u, v;
  };
  static constexpr Term kTerms[kFeatures] = {
      {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2},
      {1, 1, 0}, {1, 0, 1}, {2, 1, 0}, {2, 0, 1}, {0, 3, 0}, {0, 2, 1}, {0, 1, 2}, {0, 0, 3}};
  basis_.assign(static_cast<size_t>(dims_) * kFeatures, 0.0);
  for (int k = 0; k < kFeatures; ++k) {
    const Term t = kTerms[k];
    if (t.u >= p_ || t.v >= p_) continue;
    for (int y = 0; y < p_; ++y)
      for (int x = 0; x < p_; ++x)
        for (int c = 0; c < 3; ++c)
          basis_[static_cast<size_t>((y * p_ + x) * 3 + c) * kFeatures + k] =
              colour[t.colour][c] * dct(t.u, x) * dct(t.v, y);
  }

  // Window grid: stride 1 unless that gives more than max_windows windows.
  const int nx0 = img.w - p_ + 1, ny0 = img.h - p_ + 1;
  int stride = 1;
  auto count = [&](int s) {
    return static_cast<long long>((nx0 + s - 1) / s) * static_cast<long long>((ny0 + s - 1) / s);
  };
  while (count(stride) > max_windows) ++stride;
  n_ = static_cast<int>(count(stride));

  std::vector<uint8_t> vecs(static_cast<size_t>(n_) * padded_);
  std::vector<float> feats(static_cast<size_t>(n_) * kRows);
  std::vector<int> pos(static_cast<size_t>(n_));
  {
    int i = 0;
    for (int y = 0; y < ny0; y += stride)
      for (int x = 0; x < nx0; x += stride, ++i) {
        describe(img, x, y, &vecs[static_cast<size_t>(i) * padded_], &feats[static_cast<size_t>(i) * kRows]);
        pos[static_cast<size_t>(i)] = y * w_ + x;
      }
  }

  // k-d partition of the windows in feature space: split at a multiple of
  // kLeaf near the median of the widest coordinate until leaves hold at
  // most kLeaf windows.
  std::vector<int> order(static_cast<size_t>(n_));
  for (int i = 0; i < n_; ++i) order[static_cast<size_t>(i)] = i;
  std::vector<std::pair<int, int>> leaves;
  std::vector<std::pair<int, int>> todo = {{0, n_}};
  while (!todo.empty()) {
    const auto [lo, hi] = todo.back();
    todo.pop_back();
    if (hi - lo <= kLeaf) {
      leaves.emplace_back(lo, hi);
      continue;
    }
    float mn[kRows], mx[kRows];
    std::fill_n(mn, kRows, std::numeric_limits<float>::infinity());
    std::fill_n(mx, kRows, -std::numeric_limits<float>::infinity());
    for (int i = lo; i < hi; ++i) {
      const float* f = &feats[static_cast<size_t>(order[static_cast<size_t>(i)]) * kRows];
      for (int r = 0; r < kRows; ++r) {
        mn[r] = std::min(mn[r], f[r]);
        mx[r] = std::max(mx[r], f[r]);
      }
    }
    int dim = 0;
    for (int r = 1; r < kRows; ++r)
      if (mx[r] - mn[r] > mx[dim] - mn[dim]) dim = r;
    int mid = lo + ((hi - lo) / 2 + kLeaf / 2) / kLeaf * kLeaf;
    mid = std::clamp(mid, lo + kLeaf, hi - 1);
    std::nth_element(order.begin() + lo, order.begin() + mid, order.begin() + hi, [&](int a, int b) {
      const float fa = feats[static_cast<size_t>(a) * kRows + dim], fb = feats[static_cast<size_t>(b) * kRows + dim];
      return fa < fb || (fa == fb && a < b);
    });
    // Keep leaves in a stable left-to-right order.
    todo.emplace_back(mid, hi);
    todo.emplace_back(lo, mid);
  }

  // Lay the windows out leaf by leaf, each leaf padded to whole blocks.
  nblocks_ = 0;
  for (const auto& [lo, hi] : leaves) nblocks_ += (hi - lo + kBlock - 1) / kBlock;
  vecs_.assign(static_cast<size_t>(nblocks_) * kBlock * padded_, 0);
  blocks_.assign(static_cast<size_t>(nblocks_) * kRows * kBlock, std::numeric_limits<float>::infinity());
  pos_.assign(static_cast<size_t>(nblocks_) * kBlock, -1);
  leaf_first_.clear();
  leaf_lo_.assign(leaves.size() * kRows, 0.f);
  leaf_hi_.assign(leaves.size() * kRows, 0.f);
  int slot = 0;
  for (size_t l = 0; l < leaves.size(); ++l) {
    const auto [lo, hi] = leaves[l];
    leaf_first_.push_back(slot / kBlock);
    for (int r = 0; r < kRows; ++r) {
      leaf_lo_[l * kRows + r] = std::numeric_limits<float>::infinity();
      leaf_hi_[l * kRows + r] = -std::numeric_limits<float>::infinity();
    }
    for (int i = lo; i < hi; ++i, ++slot) {
      const int src = order[static_cast<size_t>(i)];
      std::copy_n(&vecs[static_cast<size_t>(src) * padded_], padded_, &vecs_[static_cast<size_t>(slot) * padded_]);
      pos_[static_cast<size_t>(slot)] = pos[static_cast<size_t>(src)];
      float* blk = &blocks_[static_cast<size_t>(slot / kBlock) * kRows * kBlock];
      for (int r = 0; r < kRows; ++r) {
        const float v = feats[static_cast<size_t>(src) * kRows + r];
        blk[r * kBlock + slot % kBlock] = v;
        leaf_lo_[l * kRows + r] = std::min(leaf_lo_[l * kRows + r], v);
        leaf_hi_[l * kRows + r] = std::max(leaf_hi_[l * kRows + r], v);
      }
    }
    slot = (slot + kBlock - 1) / kBlock * kBlock;
  }
  leaf_first_.push_back(nblocks_);
}

// Not inlined so that queries and windows go through identical code: the
// same bytes always give bit-identical numbers.
__attribute__((noinline)) void PatchIndex::describe(const Rgb8& im, int x0, int y0, uint8_t* vec,
                                                    float* feat) const {
  const int row_len = 3 * p_;
  for (int y = 0; y < p_; ++y)
    std::copy_n(&im.v[(static_cast<size_t>(y0 + y) * im.w + x0) * 3], row_len, vec + y * row_len);
  std::fill(vec + dims_, vec + padded_, uint8_t{0});
  double acc[kFeatures] = {};
  long long energy = 0;
  for (int j = 0; j < dims_; ++j) {
    const int v = vec[j];
    energy += v * v;
    const double dv = v;
    const double* b = &basis_[static_cast<size_t>(j) * kFeatures];
    for (int k = 0; k < kFeatures; ++k) acc[k] += dv * b[k];
  }
  double inside = 0.0;
  for (int k = 0; k < kFeatures; ++k) {
    feat[k] = static_cast<float>(acc[k]);
    inside += acc[k] * acc[k];
  }
  feat[kFeatures] = static_cast<float>(std::sqrt(std::max(0.0, static_cast<double>(energy) - inside)));
}

long long PatchIndex::ssd(const uint8_t* a, const uint8_t* b) const {
  int s = 0;  // at most 64*64*3*255^2 < 2^31
  for (int j = 0; j < padded_; ++j) {
    const int d = static_cast<int>(a[j]) - static_cast<int>(b[j]);
    s += d * d;
  }
  return s;
}

PatchIndex::Match PatchIndex::nearest(const Rgb8& query, int qx, int qy, int hint_x, int hint_y) const {
  std::vector<uint8_t> q(static_cast<size_t>(padded_) * 2);
  uint8_t* qv = q.data();
  uint8_t* hv = q.data() + padded_;
  float qf[kRows];
  describe(query, qx, qy, qv, qf);

  Match best;
  long long best_ssd = LLONG_MAX;
  if (hint_x >= 0 && hint_y >= 0 && hint_x <= img_->w - p_ && hint_y <= img_->h - p_) {
    // Any window of the image may be a hint, on the stored grid or not.
    const int row_len = 3 * p_;
    for (int y = 0; y < p_; ++y)
      std::copy_n(&img_->v[(static_cast<size_t>(hint_y + y) * img_->w + hint_x) * 3], row_len, hv + y * row_len);
    std::fill(hv + dims_, hv + padded_, uint8_t{0});
    best_ssd = ssd(qv, hv);
    best.x = hint_x;
    best.y = hint_y;
  }

  // Leaves in order of their box bound, skipping those that cannot hold a
  // better window. The closest leaf goes first, then the others in layout
  // order (neighbouring leaves are close in feature space).
  const int nleaves = static_cast<int>(leaf_first_.size()) - 1;
  std::vector<float> leaf_lb(static_cast<size_t>(nleaves));
  int first_leaf = 0;
  for (int l = 0; l < nleaves; ++l) {
    const float* lo = &leaf_lo_[static_cast<size_t>(l) * kRows];
    const float* hi = &leaf_hi_[static_cast<size_t>(l) * kRows];
    float sum = 0.f;
    for (int r = 0; r < kRows; ++r) {
      const float d = std::max({lo[r] - qf[r], qf[r] - hi[r], 0.f});
      sum += d * d;
    }
    leaf_lb[static_cast<size_t>(l)] = sum;
    if (sum < leaf_lb[static_cast<size_t>(first_leaf)]) first_leaf = l;
  }

  using v4 = float __attribute__((vector_size(16)));
  static_assert(kBlock == 8);
  v4 qb[kRows];
  for (int r = 0; r < kRows; ++r) qb[r] = v4{qf[r], qf[r], qf[r], qf[r]};
  double limit = prune_limit(best_ssd);
  auto visit = [&](int leaf) {
    for (int b = leaf_first_[static_cast<size_t>(leaf)]; b < leaf_first_[static_cast<size_t>(leaf) + 1]; ++b) {
      const float* blk = &blocks_[static_cast<size_t>(b) * kRows * kBlock];
      v4 a0 = {0, 0, 0, 0}, a1 = {0, 0, 0, 0};
      for (int r = 0; r < kRows; ++r) {
        v4 x0, x1;
        std::memcpy(&x0, blk + r * kBlock, sizeof x0);
        std::memcpy(&x1, blk + r * kBlock + 4, sizeof x1);
        const v4 d0 = x0 - qb[r], d1 = x1 - qb[r];
        a0 += d0 * d0;
        a1 += d1 * d1;
      }
      float lb[kBlock];
      std::memcpy(lb, &a0, sizeof a0);
      std::memcpy(lb + 4, &a1, sizeof a1);
      for (int lane = 0; lane < kBlock; ++lane) {
        if (static_cast<double>(lb[lane]) > limit) continue;  // also padding (infinite)
        const size_t slot = static_cast<size_t>(b) * kBlock + static_cast<size_t>(lane);
        const long long s = ssd(qv, &vecs_[slot * padded_]);
        if (s < best_ssd) {
          best_ssd = s;
          best.x = pos_[slot] % w_;
          best.y = pos_[slot] / w_;
          limit = prune_limit(best_ssd);
        }
      }
    }
  };
  visit(first_leaf);
  for (int l = 0; l < nleaves; ++l)
    if (l != first_leaf && static_cast<double>(leaf_lb[static_cast<size_t>(l)]) <= limit) visit(l);
  best.ssd = best_ssd;
  return best;
}

double mean_nn_rms(const Rgb8& query, const PatchIndex& index, int max_queries, uint64_t seed) {
  return mean_nn_rms(query, std::vector<const PatchIndex*>{&index}, max_queries, seed);
}

double mean_nn_rms(const Rgb8& query, const std::vector<const PatchIndex*>& indexes, int max_queries,
                   uint64_t seed) {
  const PatchIndex& index = *indexes.front();
  const int p = index.patch();
  require_fits(query, p, "query image");
  if (max_queries < 1) throw std::invalid_argument("vqtex_metrics: max_queries must be >= 1");
  const int nx = query.w - p + 1, ny = query.h - p + 1;
  SplitMix64 rng(seed);
  const std::vector<int> idx = sample_indices(nx * ny, max_queries, rng);
  const double dims = index.dims();
  double sum = 0.0;
  for (int id : idx) {
    long long best = -1;
    for (const PatchIndex* ix : indexes) {
      const long long ssd = ix->nearest(query, id % nx, id / nx).ssd;
      if (best < 0 || ssd < best) best = ssd;
    }
    sum += std::sqrt(static_cast<double>(best) / dims);
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

double coherence(const Image& output, const Image& exemplar, int patch, int max_queries, uint64_t seed,
                 int max_windows) {
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  const detail::PatchIndex index(ex, patch, max_windows);
  return detail::mean_nn_rms(out, index, max_queries, detail::derive_seed(seed, 4000));
}

double completeness(const Image& reference, const Image& output, int patch, int max_queries, uint64_t seed,
                    int max_windows) {
  const detail::Rgb8 ref = detail::to_rgb8(reference, "reference");
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::PatchIndex index(out, patch, max_windows);
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
