// appearance.cpp - Gaussian stack and fixed-point PCA appearance vectors
// (Lefebvre & Hoppe 2005 section 3.1, 2006 section 3). See appearance.hpp.
#include "engine/appearance.hpp"

#include <algorithm>
#include <cstdlib>

#include "common/parallel.hpp"
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

int fold(int i, int size, bool wraps) { return edge_index(i, size, wraps ? EdgeMode::Wrap : EdgeMode::Mirror); }

// The 5x5 window of `img` around (x, y) with taps `step` apart, channel by
// channel, into out (kWindowTaps * channels values).
void gather_window(const Image& img, int x, int y, int step, bool wraps, int16_t* out) {
    int xs[kWindow], ys[kWindow];
    for (int i = 0; i < kWindow; ++i) {
        const int dx = x + (i - kWindow / 2) * step, dy = y + (i - kWindow / 2) * step;
        xs[i] = dx >= 0 && dx < img.width ? dx : fold(dx, img.width, wraps);
        ys[i] = dy >= 0 && dy < img.height ? dy : fold(dy, img.height, wraps);
    }
    for (int r = 0; r < kWindow; ++r)
        for (int c = 0; c < kWindow; ++c) {
            const uint8_t* p = img.at(xs[c], ys[r]);
            for (int ch = 0; ch < img.channels; ++ch) *out++ = p[ch];
        }
}

}  // namespace

int AppearanceSpace::fold_x(int x) const { return fold(x, width, wraps); }
int AppearanceSpace::fold_y(int y) const { return fold(y, height, wraps); }

Image stack_filter(const Image& in, int step, bool wraps) {
    const int w = in.width, h = in.height, ch = in.channels;
    std::vector<int32_t> rows(std::size_t(w) * h * ch);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < ch; ++c) {
                int32_t sum = 0;
                for (int t = 0; t < 5; ++t) sum += kPyramidTaps[t] * in.at(fold(x + (t - 2) * step, w, wraps), y)[c];
                rows[(std::size_t(y) * w + x) * ch + c] = sum;
            }
    Image out(w, h, ch);
    for (int y = 0; y < h; ++y) {
        int ys[5];
        for (int t = 0; t < 5; ++t) ys[t] = fold(y + (t - 2) * step, h, wraps);
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < ch; ++c) {
                int32_t sum = 0;
                for (int t = 0; t < 5; ++t) sum += kPyramidTaps[t] * rows[(std::size_t(ys[t]) * w + x) * ch + c];
                out.at(x, y)[c] = uint8_t((sum + 128) >> 8);
            }
    }
    return out;
}

std::vector<std::vector<int32_t>> principal_axes(const std::vector<int16_t>& samples, int dims, int count,
                                                 int axes, int threads) {
    const std::size_t d = std::size_t(dims);
    // Sums of products over chunks of samples on the threads, then added:
    // integer sums, so the same whatever the split.
    constexpr std::size_t kChunk = 512;
    const std::size_t chunks = (std::size_t(count) + kChunk - 1) / kChunk;
    std::vector<std::vector<int64_t>> chunk_sum(chunks, std::vector<int64_t>(d, 0));
    std::vector<std::vector<uint32_t>> chunk_products(chunks, std::vector<uint32_t>(d * d, 0));
    parallel_for(threads, chunks, 1, [&](std::size_t c0, std::size_t c1) {
        for (std::size_t c = c0; c < c1; ++c) {
            int64_t* sum = chunk_sum[c].data();
            uint32_t* products = chunk_products[c].data();
            for (std::size_t s = c * kChunk; s < std::min(std::size_t(count), (c + 1) * kChunk); ++s) {
                const int16_t* x = samples.data() + s * d;
                for (std::size_t i = 0; i < d; ++i) {
                    sum[i] += x[i];
                    const uint32_t xi = uint32_t(x[i]);
                    uint32_t* row = products + i * d;
                    for (std::size_t j = i; j < d; ++j) row[j] += xi * uint32_t(x[j]);
                }
            }
        }
    });
    std::vector<int64_t> sum(d, 0);
    std::vector<uint32_t> products(d * d, 0);
    for (std::size_t c = 0; c < chunks; ++c)
        for (std::size_t i = 0; i < d * d; ++i) {
            products[i] += chunk_products[c][i];
            if (i < d) sum[i] += chunk_sum[c][i];
        }
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
    std::vector<int64_t> k(d * d);
    for (std::size_t i = 0; i < d * d; ++i) k[i] = int64_t(cov[i] >> shift);

    std::vector<std::vector<int64_t>> found;  // Q30
    std::vector<std::vector<int32_t>> result(std::size_t(axes), std::vector<int32_t>(d, 0));
    std::vector<int64_t> v(d), w(d);
    uint64_t strongest = 0;  // |K v| of the first axis, once converged
    for (int a = 0; a < axes; ++a) {
        for (std::size_t i = 0; i < d; ++i) v[i] = int64_t(1 + (i * 7 + std::size_t(a) * 13) % 5) << 24;
        bool zero = false;
        for (int it = 0; it < kPowerIterations && !zero; ++it) {
            for (std::size_t i = 0; i < d; ++i) {
                int64_t acc = 0;
                const int64_t* row = k.data() + i * d;
                for (std::size_t j = 0; j < d; ++j) acc += row[j] * v[j];
                w[i] = acc >> 24;
            }
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
            for (std::size_t i = 0; i < d; ++i) v[i] = int64_t((int128(w[i]) << kAxisShift) / int128(norm));
        }
        if (zero) break;  // no variance left: this and later axes stay zero
        found.push_back(v);
        for (std::size_t i = 0; i < d; ++i) result[std::size_t(a)][i] = int32_t((v[i] + (1 << 14)) >> 15);
    }
    return result;
}

AppearanceSpace build_appearance_space(const Image& example, int levels, bool wraps, int threads) {
    std::vector<AppearanceSpace> frames = build_appearance_frames({example}, levels, wraps, threads);
    return std::move(frames[0]);
}

std::vector<AppearanceSpace> build_appearance_frames(const std::vector<Image>& examples, int levels, bool wraps,
                                                     int threads) {
    const std::size_t frames = examples.size();
    std::vector<AppearanceSpace> spaces(frames);
    const int w = examples[0].width, h = examples[0].height, ch = examples[0].channels;
    const int dims = kWindowTaps * ch;
    const std::size_t n = examples[0].pixel_count();
    // PCA samples on a regular grid in x and y (and every frame_step-th
    // frame), at most kMaxPcaSamples of them in all.
    const std::size_t frame_step = (frames + kMaxPcaSamples - 1) / kMaxPcaSamples;
    const std::size_t sampled_frames = (frames + frame_step - 1) / frame_step;
    int stride = 1;
    while ((std::size_t((w + stride - 1) / stride) * std::size_t((h + stride - 1) / stride)) * sampled_frames >
           std::size_t(kMaxPcaSamples))
        ++stride;
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
        // One set of axes for all the frames, so that appearance vectors of
        // different frames compare.
        std::vector<int16_t> samples;
        int count = 0;
        std::vector<int16_t> window(static_cast<std::size_t>(dims));
        for (std::size_t f = 0; f < frames; f += frame_step)
            for (int y = 0; y < h; y += stride)
                for (int x = 0; x < w; x += stride) {
                    gather_window(spaces[f].levels.back().colours, x, y, spacing, wraps, window.data());
                    samples.insert(samples.end(), window.begin(), window.end());
                    ++count;
                }
        const std::vector<std::vector<int32_t>> axes = principal_axes(samples, dims, count, kAppearanceDims, threads);
        std::vector<int64_t> mean(std::size_t(dims), 0);
        for (int s = 0; s < count; ++s)
            for (int i = 0; i < dims; ++i) mean[std::size_t(i)] += samples[std::size_t(s) * dims + i];
        for (auto& m : mean) m = (m + count / 2) / count;
        // Projections in the example's own units (a unit axis keeps a
        // window's length), so distances compare with colour differences.
        std::vector<int32_t> flat(std::size_t(kAppearanceDims) * dims);
        for (int a = 0; a < kAppearanceDims; ++a)
            for (int i = 0; i < dims; ++i) flat[std::size_t(a) * dims + i] = axes[std::size_t(a)][std::size_t(i)];

        for (std::size_t f = 0; f < frames; ++f) {
            AppearanceLevel& level = spaces[f].levels.back();
            const Image& img = level.colours;
            level.features.assign(n * kAppearanceDims, 0);
            parallel_for(threads, std::size_t(h), 8, [&](std::size_t y0, std::size_t y1) {
                std::vector<int16_t> win(static_cast<std::size_t>(dims));
                std::vector<int32_t> centred(static_cast<std::size_t>(dims));
                for (std::size_t y = y0; y < y1; ++y)
                    for (int x = 0; x < w; ++x) {
                        gather_window(img, x, int(y), spacing, wraps, win.data());
                        for (int i = 0; i < dims; ++i)
                            centred[std::size_t(i)] = win[std::size_t(i)] - int32_t(mean[std::size_t(i)]);
                        int16_t* fv = level.features.data() + (y * std::size_t(w) + std::size_t(x)) * kAppearanceDims;
                        for (int a = 0; a < kAppearanceDims; ++a) {
                            const int32_t* axis = flat.data() + std::size_t(a) * dims;
                            // 32 bits hold the sum exactly: a unit axis (Q15)
                            // against at most 100 values below 256 in size
                            // sums to under 2^15 * 255 * sqrt(100) < 2^27
                            // (Cauchy-Schwarz); and 32-bit lanes vectorise.
                            int32_t acc = 0;
                            for (int i = 0; i < dims; ++i) acc += axis[i] * centred[std::size_t(i)];
                            const int64_t v = (int64_t(acc) + (1 << 14)) >> 15;
                            fv[a] = int16_t(std::clamp<int64_t>(v, -kAppearanceClamp, kAppearanceClamp));
                        }
                    }
            });
        }
    }
    return spaces;
}

}  // namespace vqtex
