// appearance.cpp - Gaussian stack and fixed-point PCA appearance vectors
// (Lefebvre & Hoppe 2005 section 3.1, 2006 section 3). See appearance.hpp.
#include "engine/appearance.hpp"

#include <algorithm>
#include <cstdlib>

#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/pyramid.hpp"

namespace vqtex {
namespace {

__extension__ typedef __int128 int128;
__extension__ typedef unsigned __int128 uint128;

constexpr int kWindow = 5;  // appearance vectors summarise a 5x5 window
constexpr int kWindowTaps = kWindow * kWindow;
// Covariance sums are 32-bit: 255 * 255 * this many samples still fits.
// The axes need far fewer: 4096 samples on a regular grid (every other
// pixel of a 128x128 example) scored as all 16384 on the corpus.
constexpr int kMaxPcaSamples = 4096;
constexpr int kPowerIterations = 40;
constexpr int kAxisShift = 30;  // unit vectors in Q30 while iterating

uint64_t isqrt(uint128 n) {
    if (n == 0) return 0;
    int bits = 0;
    for (uint128 m = n; m; m >>= 1) ++bits;
    uint128 x = uint128(1) << ((bits + 1) / 2);  // at or above the root
    for (;;) {
        const uint128 y = (x + n / x) >> 1;
        if (y >= x) return uint64_t(x);
        x = y;
    }
}

// (n << kAxisShift) / d rounded toward zero, for |n| <= d (a component of
// a vector of length d, so the quotient is at most 2^kAxisShift), with
// scale = 2^kAxisShift / d: the power iteration's normalisation. A
// floating-point estimate, off by at most one, then exact integer steps to
// the quotient: the same integer on every machine, without a 128-bit
// division per component (which made this the analysis's slowest loop).
int64_t scaled_quotient(int64_t n, uint64_t d, double scale) {
    const uint64_t m = n < 0 ? 0 - uint64_t(n) : uint64_t(n);
    const uint128 target = uint128(m) << kAxisShift;
    uint64_t q = uint64_t(double(m) * scale);
    while (q > 0 && uint128(q) * d > target) --q;
    while (uint128(q + 1) * d <= target) ++q;
    return n < 0 ? -int64_t(q) : int64_t(q);
}

int fold(int i, int size, bool wraps) { return edge_index(i, size, wraps ? EdgeMode::Wrap : EdgeMode::Mirror); }

// The appearance vectors of one stack level: every pixel's 5x5 window at
// `spacing` projected on `axes` (Q15), less `offset` (the axes times the
// mean window), rounded and clamped. Rather than gathering each pixel's
// window, the kernel (Kernels::project_pairs) reads whole rows of the
// level, each value beside the value `spacing` to its right: a pair plane
// per channel, padded by two taps on each side as the window reads past the
// edges. A window row's five taps are three such pairs: columns 0-1, 2-3,
// and 3-4 with no weight on column 3, so that no pair reads beyond the
// window.
void project_level(const Image& img, int spacing, bool wraps, const std::vector<std::vector<int32_t>>& axes,
                   const std::vector<int32_t>& offset, int threads, int16_t* features) {
    const int w = img.width, h = img.height, ch = img.channels;
    const int pad = 2 * spacing;
    // Pair (x, y) holds plane values x and x + spacing of padded row y.
    const std::size_t pw = std::size_t(w + 3 * spacing), ph = std::size_t(h + 2 * pad);
    std::vector<int16_t> pairs(pw * ph * std::size_t(ch) * 2);
    std::vector<std::size_t> source_x(pw + std::size_t(spacing));
    for (std::size_t x = 0; x < source_x.size(); ++x) source_x[x] = std::size_t(fold(int(x) - pad, w, wraps)) * ch;
    for (int c = 0; c < ch; ++c)
        for (std::size_t y = 0; y < ph; ++y) {
            const uint8_t* source = img.at(0, fold(int(y) - pad, h, wraps)) + c;
            int16_t* pair_row = pairs.data() + (std::size_t(c) * ph + y) * pw * 2;
            for (std::size_t x = 0; x < pw; ++x) {
                pair_row[2 * x] = source[source_x[x]];
                pair_row[2 * x + 1] = source[source_x[x + std::size_t(spacing)]];
            }
        }
    // The entries: per window row and channel, three pairs of columns, each
    // with its eight axes' pairs of weights (the low half for the first
    // column). A weight fits 16 bits but for a unit axis along one value
    // (2^15 exactly): that pair goes in twice, with half the weight each
    // time, the sums being the same integers modulo 2^32.
    constexpr int kPairColumn[3] = {0, 2, 3};
    struct Entry {
        int row, channel, column;
    };
    std::vector<Entry> entries;
    std::vector<int32_t> weights;
    for (int r = 0; r < kWindow; ++r)
        for (int k = 0; k < ch; ++k)
            for (int p = 0; p < 3; ++p) {
                const int c = kPairColumn[p];
                int32_t first[kAppearanceDims], second[kAppearanceDims];
                bool halve = false;
                for (int a = 0; a < kAppearanceDims; ++a) {
                    const std::vector<int32_t>& axis = axes[std::size_t(a)];
                    first[a] = p == 2 ? 0 : axis[std::size_t((r * kWindow + c) * ch + k)];
                    second[a] = axis[std::size_t((r * kWindow + c + 1) * ch + k)];
                    halve = halve || first[a] == 32768 || second[a] == 32768;
                }
                // Part 0 (only when halved) takes half of each weight, part
                // 1 the rest.
                for (int part = halve ? 0 : 1; part < 2; ++part) {
                    entries.push_back({r, k, c});
                    for (int a = 0; a < kAppearanceDims; ++a) {
                        const int32_t half0 = halve ? first[a] / 2 : 0, half1 = halve ? second[a] / 2 : 0;
                        const int32_t w0 = part == 0 ? half0 : first[a] - half0;
                        const int32_t w1 = part == 0 ? half1 : second[a] - half1;
                        weights.push_back(
                            int32_t(uint32_t(uint16_t(int16_t(w0))) | uint32_t(uint16_t(int16_t(w1))) << 16));
                    }
                }
            }
    const dsp::Kernels& kernels = dsp::kernels();
    parallel_for(threads, std::size_t(h), 8, [&](std::size_t y0, std::size_t y1) {
        std::vector<const int16_t*> rows(entries.size());
        for (std::size_t y = y0; y < y1; ++y) {
            for (std::size_t e = 0; e < entries.size(); ++e) {
                const Entry& entry = entries[e];
                rows[e] = pairs.data() +
                          ((std::size_t(entry.channel) * ph + y + std::size_t(entry.row * spacing)) * pw +
                           std::size_t(entry.column * spacing)) * 2;
            }
            // (Sums and offsets lie within 2^27, level_features says why:
            // within the kernel's bounds.)
            kernels.project_pairs(rows.data(), weights.data(), entries.size(), std::size_t(w), offset.data(),
                                  kAppearanceClamp, features + y * std::size_t(w) * kAppearanceDims);
        }
    });
}

}  // namespace

int AppearanceSpace::fold_x(int x) const { return fold(x, width, wraps); }
int AppearanceSpace::fold_y(int y) const { return fold(y, height, wraps); }

Image stack_filter(const Image& in, int step, bool wraps) {
    // Rows are read through a copy padded by two taps on each side, so that
    // the inner loops run over contiguous values with no edge test and
    // vectorise; the sums are the same integers in any order.
    const int w = in.width, h = in.height, ch = in.channels;
    const std::size_t row_values = std::size_t(w) * ch;
    const std::size_t tap_stride = std::size_t(step) * ch;
    std::vector<uint16_t> rows(row_values * h);  // horizontal sums, at most 16 * 255
    std::vector<uint16_t> padded(std::size_t(w + 4 * step) * ch);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w + 4 * step; ++x) {
            const uint8_t* p = in.at(fold(x - 2 * step, w, wraps), y);
            for (int c = 0; c < ch; ++c) padded[std::size_t(x) * ch + c] = p[c];
        }
        uint16_t* out = rows.data() + std::size_t(y) * row_values;
        for (std::size_t i = 0; i < row_values; ++i) {
            uint16_t sum = 0;
            for (int t = 0; t < 5; ++t) sum = uint16_t(sum + kPyramidTaps[t] * padded[i + std::size_t(t) * tap_stride]);
            out[i] = sum;
        }
    }
    Image out(w, h, ch);
    for (int y = 0; y < h; ++y) {
        const uint16_t* r[5];
        for (int t = 0; t < 5; ++t) r[t] = rows.data() + std::size_t(fold(y + (t - 2) * step, h, wraps)) * row_values;
        uint8_t* o = out.at(0, y);
        for (std::size_t i = 0; i < row_values; ++i) {
            uint32_t sum = 0;
            for (int t = 0; t < 5; ++t) sum += uint32_t(kPyramidTaps[t]) * r[t][i];
            o[i] = uint8_t((sum + 128) >> 8);
        }
    }
    return out;
}

std::vector<std::vector<int32_t>> principal_axes(const std::vector<int16_t>& columns, int dims, int count, int axes,
                                                 int threads, std::vector<int64_t>* sums) {
    const std::size_t d = std::size_t(dims), n = std::size_t(count);
    // Sums of products of every pair of components, as dot products of the
    // columns (contiguous 16-bit values, a vector kernel). Integer sums
    // modulo 2^32, so the same in any order or split.
    std::vector<int64_t> sum(d, 0);
    std::vector<uint32_t> products(d * d, 0);
    const dsp::Kernels& kernels = dsp::kernels();
    // Rows in groups of 4 (the widest kernel's block), taken by the threads
    // as they come free: the rows have fewer products down the triangle.
    constexpr std::size_t kRowsAtOnce = 4;
    parallel_for(threads, d, kRowsAtOnce, [&](std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
            const int16_t* a = columns.data() + i * n;
            // 32-bit partial sums (65536 values of 16 bits fit) vectorise:
            // with the end a value of its own (std::min's reference to a
            // temporary was read again at every step, and the loop ran
            // scalar: 6% of the analysis).
            int64_t total = 0;
            for (std::size_t s0 = 0; s0 < n; s0 += 65536) {
                const std::size_t end = std::min(n, s0 + 65536);
                int32_t part = 0;
                for (std::size_t s = s0; s < end; ++s) part += a[s];
                total += part;
            }
            sum[i] = total;
        }
        kernels.gram_i16(columns.data(), d, n, i0, i1, products.data());
    });
    if (sums) *sums = sum;
    // count^2 times the covariance, exact, then scaled so that every entry
    // is below 2^24: a row times a Q30 vector then fits 64 bits.
    std::vector<int128> cov(d * d);
    int128 largest = 0;
    for (std::size_t i = 0; i < d; ++i)
        for (std::size_t j = i; j < d; ++j) {
            const int128 c = int128(count) * products[i * d + j] - int128(sum[i]) * sum[j];
            cov[i * d + j] = cov[j * d + i] = c;
            largest = std::max(largest, c < 0 ? -c : c);
        }
    int shift = 0;
    while ((largest >> shift) >= (int128(1) << 24)) ++shift;
    // Entries below 2^24 and unit vectors in Q30 both fit 32 bits: the
    // matrix-vector products are 32x32->64-bit multiplies (a vector kernel).
    std::vector<int32_t> k(d * d);
    for (std::size_t i = 0; i < d * d; ++i) k[i] = int32_t(cov[i] >> shift);

    std::vector<std::vector<int64_t>> found;  // Q30
    std::vector<std::vector<int32_t>> result(std::size_t(axes), std::vector<int32_t>(d, 0));
    std::vector<int64_t> v(d), w(d);
    std::vector<int32_t> v32(d);
    uint64_t strongest = 0;  // |K v| of the first axis, once converged
    for (int a = 0; a < axes; ++a) {
        for (std::size_t i = 0; i < d; ++i) v[i] = int64_t(1 + (i * 7 + std::size_t(a) * 13) % 5) << 24;
        bool zero = false;
        for (int it = 0; it < kPowerIterations && !zero; ++it) {
            for (std::size_t i = 0; i < d; ++i) v32[i] = int32_t(v[i]);  // |v| <= 2^30
            kernels.matvec_i32(k.data(), v32.data(), d, w.data());  // k is symmetric: v k = k v
            for (std::size_t i = 0; i < d; ++i) w[i] >>= 24;
            for (const auto& e : found) {
                int128 dot = 0;
                for (std::size_t i = 0; i < d; ++i) dot += int128(e[i]) * w[i];
                for (std::size_t i = 0; i < d; ++i) w[i] -= int64_t((int128(e[i]) * dot) >> (2 * kAxisShift));
            }
            uint128 norm2 = 0;
            for (std::size_t i = 0; i < d; ++i) norm2 += uint128(int128(w[i]) * w[i]);
            const uint64_t norm = isqrt(norm2);
            // Variance below 1/4096 of the strongest axis's is rounding
            // noise: scaled up to unit length it would not be orthogonal.
            if (a == 0 && it + 1 == kPowerIterations) strongest = norm;
            if (norm == 0 || (a > 0 && norm < strongest / 4096 + 1)) {
                zero = true;
                break;
            }
            const double scale = double(int64_t(1) << kAxisShift) / double(norm);
            for (std::size_t i = 0; i < d; ++i) v[i] = scaled_quotient(w[i], norm, scale);
        }
        if (zero) break;  // no variance left: this and later axes stay zero
        found.push_back(v);
        for (std::size_t i = 0; i < d; ++i) result[std::size_t(a)][i] = int32_t((v[i] + (1 << 14)) >> 15);
    }
    return result;
}

namespace {

// Level l's principal axes (one set for all the frames, so that appearance
// vectors of different frames compare) and every frame's appearance vectors
// at that level, from the level's colours.
void level_features(AppearanceSpace* spaces, std::size_t frames, int l, int threads) {
    const int w = spaces[0].width, h = spaces[0].height, ch = spaces[0].levels[0].colours.channels;
    const bool wraps = spaces[0].wraps;
    const int dims = kWindowTaps * ch;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    // PCA samples on a regular grid in x and y (and every frame_step-th
    // frame), at most kMaxPcaSamples of them in all.
    const std::size_t frame_step = (frames + kMaxPcaSamples - 1) / kMaxPcaSamples;
    const std::size_t sampled_frames = (frames + frame_step - 1) / frame_step;
    int stride = 1;
    while ((std::size_t((w + stride - 1) / stride) * std::size_t((h + stride - 1) / stride)) * sampled_frames >
           std::size_t(kMaxPcaSamples))
        ++stride;
    const int spacing = spaces[0].levels[std::size_t(l)].spacing;
    // The samples' windows go straight into columns, one per window
    // value (tap and channel), as principal_axes takes them; filled a
    // column at a time, so that the writes are in order.
    const int grid_w = (w + stride - 1) / stride, grid_h = (h + stride - 1) / stride;
    const int count = int(sampled_frames) * grid_w * grid_h;
    // tap_x holds byte offsets in a row (the column times the channels).
    std::vector<int> tap_x(std::size_t(kWindow) * grid_w), tap_y(std::size_t(kWindow) * grid_h);
    for (int t = 0; t < kWindow; ++t) {
        for (int g = 0; g < grid_w; ++g)
            tap_x[std::size_t(t * grid_w + g)] = fold(g * stride + (t - 2) * spacing, w, wraps) * ch;
        for (int g = 0; g < grid_h; ++g)
            tap_y[std::size_t(t * grid_h + g)] = fold(g * stride + (t - 2) * spacing, h, wraps);
    }
    // Where the spacing is a whole number of grid steps, tap column c reads
    // at grid column gx the example pixel that tap column c - 1 reads at gx
    // + shift (the same coordinate before folding): all but the last
    // `shift` values of each of its grid rows are copied from the column of
    // the tap before, and only those are read through the tables.
    const int shift = spacing % stride == 0 && spacing / stride < grid_w ? spacing / stride : 0;
    std::vector<int16_t> columns(std::size_t(dims) * std::size_t(count));
    for (int r = 0; r < kWindow; ++r)
        for (int c = 0; c < kWindow; ++c)
            for (int k = 0; k < ch; ++k) {
                int16_t* column = columns.data() + std::size_t((r * kWindow + c) * ch + k) * std::size_t(count);
                const int16_t* left = column - std::size_t(ch) * std::size_t(count);  // tap (r, c - 1), channel k
                const int copied = c > 0 ? shift : 0;
                for (std::size_t f = 0; f < frames; f += frame_step) {
                    const Image& img = spaces[f].levels[std::size_t(l)].colours;
                    for (int gy = 0; gy < grid_h; ++gy) {
                        if (copied > 0) std::copy_n(left + copied, grid_w - copied, column);
                        const uint8_t* row = img.at(0, tap_y[std::size_t(r * grid_h + gy)]);
                        const int* xs = tap_x.data() + std::size_t(c * grid_w);
                        const uint8_t* values = row + k;
                        for (int gx = grid_w - (copied > 0 ? copied : grid_w); gx < grid_w; ++gx) column[gx] = values[xs[gx]];
                        column += grid_w;
                        left += grid_w;
                    }
                }
            }
    std::vector<int64_t> mean;  // the columns' sums, then their rounded means
    const std::vector<std::vector<int32_t>> axes =
        principal_axes(columns, dims, count, kAppearanceDims, threads, &mean);
    for (auto& m : mean) m = (m + count / 2) / count;
    // Projections in the example's own units (a unit axis keeps a
    // window's length), so distances compare with colour differences:
    // sum over the window of axis * (value - mean), computed as the
    // sum of axis * value less the constant sum of axis * mean. Both are
    // exact 32-bit integers (a unit axis in Q15 against at most 100
    // values below 256 sums to under 2^15 * 255 * sqrt(100) < 2^27 by
    // Cauchy-Schwarz, and the mean is a window too), so the difference
    // is the centred sum itself.
    std::vector<int32_t> offset(kAppearanceDims, 0);
    for (int a = 0; a < kAppearanceDims; ++a)
        for (int i = 0; i < dims; ++i)
            offset[std::size_t(a)] += axes[std::size_t(a)][std::size_t(i)] * int32_t(mean[std::size_t(i)]);
    for (std::size_t f = 0; f < frames; ++f) {
        AppearanceLevel& level = spaces[f].levels[std::size_t(l)];
        level.features.assign(n * kAppearanceDims, 0);
        project_level(level.colours, spacing, wraps, axes, offset, threads, level.features.data());
    }
}

}  // namespace

AppearanceSpace build_appearance_space(const Image& example, int levels, bool wraps, int threads,
                                       bool with_features) {
    std::vector<AppearanceSpace> frames = build_appearance_frames({example}, levels, wraps, threads, with_features);
    return std::move(frames[0]);
}

void build_level_features(AppearanceSpace& space, int level, int threads) {
    level_features(&space, 1, level, threads);
}

std::vector<AppearanceSpace> build_appearance_frames(const std::vector<Image>& examples, int levels, bool wraps,
                                                     int threads, bool with_features) {
    const std::size_t frames = examples.size();
    std::vector<AppearanceSpace> spaces(frames);
    const int w = examples[0].width, h = examples[0].height, ch = examples[0].channels;
    const std::size_t n = examples[0].pixel_count();
    for (std::size_t f = 0; f < frames; ++f) {
        AppearanceSpace& space = spaces[f];
        space.width = w;
        space.height = h;
        space.wraps = wraps;
        space.pixels.assign(n * kAppearanceDims, 0);
        const Image& example = examples[f];
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < ch; ++c)
                space.pixels[i * kAppearanceDims + std::size_t(c)] =
                    int16_t(4 * example.pixels[i * std::size_t(ch) + std::size_t(c)]);
    }
    for (int l = 0; l < levels; ++l) {
        const int spacing = 1 << l;
        for (std::size_t f = 0; f < frames; ++f) {
            AppearanceLevel level;
            level.spacing = spacing;
            level.colours = l == 0 ? examples[f] : stack_filter(spaces[f].levels.back().colours, 1 << (l - 1), wraps);
            spaces[f].levels.push_back(std::move(level));
        }
    }
    if (!with_features) return spaces;
    // Each level's axes and vectors depend on that level's colours alone:
    // the levels share the threads (the power iteration is serial), and
    // what is left of them goes to each level's loops. Exact integers, so
    // the same for any split.
    const int level_threads = std::max(1, threads / std::max(levels, 1));
    parallel_for(threads, std::size_t(std::max(levels, 0)), 1, [&](std::size_t l0, std::size_t l1) {
        for (int l = int(l0); l < int(l1); ++l) level_features(spaces.data(), frames, l, level_threads);
    });
    return spaces;
}

}  // namespace vqtex
