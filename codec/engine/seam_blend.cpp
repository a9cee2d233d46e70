// seam_blend.cpp - blending the copies that meet at the output's seams
// (Kwatra et al. 2005's averaging, Wexler et al. 2007's voting). See
// seam_blend.hpp.
#include "engine/seam_blend.hpp"

#include <algorithm>
#include <type_traits>
#include <vector>

#include "common/parallel.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/copy_links.hpp"

namespace vqtex {
namespace {

// Binomial weights by radius: a window's weight is the product of its
// column's and its row's, at most 64 x 64, so a pixel's sum fits in 32 bits.
constexpr int kWeights[kMaxBlendRadius + 1][2 * kMaxBlendRadius + 1] = {
    {1}, {1, 2, 1}, {1, 4, 6, 4, 1}, {1, 6, 15, 20, 15, 6, 1}};

// Pixel (x, y)'s blend at a seam, for C channels: `source(dx, dy)` is
// the example pixel (C samples) that the neighbour at offset (dx, dy) puts
// at (x, y), or nullptr when its copy does not reach it. With
// kStraightAlpha, the last of C channels is straight (unassociated) alpha
// and colour is weighted by each tap's alpha as well, so that a
// transparent copy's colour (often black) does not darken an opaque one
// where they meet; where every tap is transparent, colour is weighted as
// alpha is. `continues(dx, dy)` (dx > -r) may say that the neighbour at
// (dx, dy) holds the next pixel of the copy of the one before it in its
// row, and so puts the same example pixel at (x, y): such taps add their
// weight to a run, whose pixel is read once, for the same sums (weights
// are factors of each tap's term).
template <int C, bool kStraightAlpha, typename T, typename Source, typename Continues>
void blend_pixel(int r, const Source& source, const Continues& continues, T* dst) {
    const int* weight = kWeights[r];
    // Sums of a tap's weight (at most 64 x 64) times a byte fit 32 bits;
    // times alpha and colour, or of 16-bit samples, they need 64.
    using Sum = std::conditional_t<kStraightAlpha || (sizeof(T) > 1), uint64_t, uint32_t>;
    Sum sum[C] = {}, weighted[C] = {}, total = 0, alpha = 0;
    const auto add = [&](const T* src, Sum wt) {
        if (!src) return;
        for (int c = 0; c < C; ++c) sum[c] += wt * src[c];
        if constexpr (kStraightAlpha) {
            for (int c = 0; c < C - 1; ++c) weighted[c] += wt * src[C - 1] * src[c];
            alpha += wt * src[C - 1];
        }
        total += wt;
    };
    for (int dy = -r; dy <= r; ++dy) {
        const T* run = source(-r, dy);
        Sum run_weight = Sum(weight[0]);
        for (int dx = -r + 1; dx <= r; ++dx) {
            if (continues(dx, dy)) {
                run_weight += Sum(weight[dx + r]);
                continue;
            }
            add(run, run_weight * Sum(weight[dy + r]));
            run = source(dx, dy);
            run_weight = Sum(weight[dx + r]);
        }
        add(run, run_weight * Sum(weight[dy + r]));
    }
    for (int c = 0; c < C; ++c) {
        const bool by_alpha = kStraightAlpha && c < C - 1 && alpha > 0;
        dst[c] = T(by_alpha ? (weighted[c] + alpha / 2) / alpha : (sum[c] + total / 2) / total);
    }
}

// blend_pixel for the channel count and alpha rule of `channels` and
// `straight_alpha`.
template <typename T, typename Source, typename Continues>
void blend_any_pixel(int channels, bool straight_alpha, int r, const Source& source, const Continues& continues,
                     T* dst) {
    switch (channels + (straight_alpha ? 4 : 0)) {
        case 1: case 5: blend_pixel<1, false>(r, source, continues, dst); break;
        case 2: blend_pixel<2, false>(r, source, continues, dst); break;
        case 3: case 7: blend_pixel<3, false>(r, source, continues, dst); break;
        case 4: blend_pixel<4, false>(r, source, continues, dst); break;
        case 6: blend_pixel<2, true>(r, source, continues, dst); break;
        default: blend_pixel<4, true>(r, source, continues, dst); break;
    }
}

// The example pixel at (sx, sy), wrapped when the example wraps, nullptr
// past its edge otherwise.
template <typename T>
const T* example_pixel(const BasicImage<T>& example, bool wraps, int sx, int sy) {
    if (wraps) {
        sx = Image::wrap(sx, example.width);
        sy = Image::wrap(sy, example.height);
    } else if (unsigned(sx) >= unsigned(example.width) || unsigned(sy) >= unsigned(example.height)) {
        return nullptr;
    }
    return example.at(sx, sy);
}

template <typename T>
void blend_rows_of(const BasicImage<T>& example, bool wraps, int radius,
                   const std::function<const uint32_t*(int)>& row_at, int first, int count, BasicImage<T>& out,
                   int threads, bool straight_alpha) {
    const int r = std::clamp(radius, 0, kMaxBlendRadius);
    const int w = out.width;
    const std::size_t channels = std::size_t(example.channels);
    const int ew = example.width, eh = example.height;
    if (r == 0) {
        // Every pixel copied: no window to check.
        parallel_for(threads, std::size_t(count), 16, [&](std::size_t i0, std::size_t i1) {
            for (std::size_t i = i0; i < i1; ++i) {
                const uint32_t* positions = row_at(first + int(i));
                T* dst = out.at(0, first + int(i));
                for (int x = 0; x < w; ++x, dst += channels)
                    copy_pixel(dst, example.at(position_x(positions[x]), position_y(positions[x])), example.channels);
            }
        });
        return;
    }
    // A centre at least r inside the example: the window check below is
    // exact there (packed positions add without carrying across fields).
    const uint32_t inside_x = uint32_t(std::max(0, ew - 2 * r)), inside_y = uint32_t(std::max(0, eh - 2 * r));
    const bool narrow = w < 2 * r + 1;  // the window's columns wrap more than once
    parallel_for(threads, std::size_t(count), 16, [&](std::size_t i0, std::size_t i1) {
        const int y0 = first + int(i0), y1 = first + int(i1);
        const int rows = y1 - y0 + 2 * r;  // map rows y0 - r .. y1 + r - 1
        std::vector<const uint32_t*> row(static_cast<std::size_t>(rows));
        for (int i = 0; i < rows; ++i) row[std::size_t(i)] = row_at(y0 - r + i);
        // Per local row: its runs, and the links down to the next row.
        std::vector<uint8_t> runs(std::size_t(rows) * w), down(std::size_t(std::max(rows - 1, 0)) * w),
            links(std::size_t(w) + 2 * std::size_t(r));
        for (int i = 0; i < rows; ++i) {
            coherent::window_runs(row[std::size_t(i)], w, r, 1, links.data(), runs.data() + std::size_t(i) * w);
            if (i + 1 < rows)
                coherent::window_down(row[std::size_t(i)], row[std::size_t(i) + 1], w, uint32_t(1) << 16,
                                      down.data() + std::size_t(i) * w);
        }
        int xs[2 * kMaxBlendRadius + 1];
        std::vector<uint8_t> whole(static_cast<std::size_t>(w));
        for (int y = y0; y < y1; ++y) {
            const int local = y - y0 + r;  // the centre row among `row`
            const uint32_t* centre = row[std::size_t(local)];
            // The whole window continues the centre when every row's links
            // hold and the centre column's links down do (each tap is then
            // the centre's position plus its offset).
            coherent::whole_windows(centre, runs.data() + std::size_t(local - r) * w,
                                    down.data() + std::size_t(local - r) * w, w, r, uint32_t(r), inside_x, inside_y,
                                    whole.data());
            T* dst = out.at(0, y);
            for (int x = 0; x < w; ++x, dst += channels) {
                const uint32_t own = centre[x];
                if (whole[std::size_t(x)]) {
                    copy_pixel(dst, example.at(position_x(own), position_y(own)), example.channels);
                    continue;
                }
                // (Columns wrapped by a comparison where the output is
                // wider than the window: a division each cost more.)
                for (int dx = -r; dx <= r; ++dx) {
                    const int c = x + dx;
                    xs[dx + r] = !narrow ? (c < 0 ? c + w : c >= w ? c - w : c) : Image::wrap(c, w);
                }
                const uint32_t* const* window = row.data() + (local - r);
                blend_any_pixel(example.channels, straight_alpha, r,
                                [&](int dx, int dy) {
                                    const uint32_t p = window[dy + r][xs[dx + r]];
                                    return example_pixel(example, wraps, position_x(p) - dx, position_y(p) - dy);
                                },
                                [&](int dx, int dy) {
                                    // The next pixel of the same copy: x one more,
                                    // y the same (packed positions add, x < 2^16).
                                    const uint32_t* taps = window[dy + r];
                                    return taps[xs[dx + r]] == taps[xs[dx + r - 1]] + 1u;
                                },
                                dst);
            }
        }
    });
}

}  // namespace

void blend_rows(const Image& example, bool wraps, int radius, const std::function<const uint32_t*(int)>& row_at,
                int first, int count, Image& out, int threads, bool straight_alpha) {
    blend_rows_of(example, wraps, radius, row_at, first, count, out, threads, straight_alpha);
}

void blend_rows(const Image16& example, bool wraps, int radius, const std::function<const uint32_t*(int)>& row_at,
                int first, int count, Image16& out, int threads, bool straight_alpha) {
    blend_rows_of(example, wraps, radius, row_at, first, count, out, threads, straight_alpha);
}

void blend_voxels(const std::vector<Image>& frames, bool wraps, int radius, const uint64_t* voxels, Image& out,
                  int threads) {
    const int r = std::clamp(radius, 0, kMaxBlendRadius);
    const int w = out.width, h = out.height, channels = out.channels;
    const bool straight_alpha = channels == 2 || channels == 4;
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        int xs[2 * kMaxBlendRadius + 1], ys[2 * kMaxBlendRadius + 1];
        for (int y = int(y0); y < int(y1); ++y) {
            for (int d = -r; d <= r; ++d) ys[d + r] = Image::wrap(y + d, h);
            uint8_t* dst = out.at(0, y);
            for (int x = 0; x < w; ++x, dst += channels) {
                const uint64_t own = voxels[std::size_t(y) * w + x];
                const Image& frame = frames[std::size_t(voxel_t(own))];
                for (int d = -r; d <= r; ++d) xs[d + r] = Image::wrap(x + d, w);
                // Inside a copy every neighbour holds the centre's voxel
                // plus its offset, and proposes the centre's own pixel.
                bool whole = true;
                for (int dy = -r; dy <= r && whole; ++dy)
                    for (int dx = -r; dx <= r; ++dx) {
                        const uint64_t v = voxels[std::size_t(ys[dy + r]) * w + std::size_t(xs[dx + r])];
                        if (voxel_t(v) != voxel_t(own) || voxel_x(v) != voxel_x(own) + dx ||
                            voxel_y(v) != voxel_y(own) + dy) {
                            whole = false;
                            break;
                        }
                    }
                if (whole) {
                    copy_pixel(dst, frame.at(voxel_x(own), voxel_y(own)), channels);
                    continue;
                }
                blend_any_pixel(channels, straight_alpha, r,
                                [&](int dx, int dy) {
                                    const uint64_t v = voxels[std::size_t(ys[dy + r]) * w + std::size_t(xs[dx + r])];
                                    return example_pixel(frames[std::size_t(voxel_t(v))], wraps, voxel_x(v) - dx,
                                                         voxel_y(v) - dy);
                                },
                                [](int, int) { return false; }, dst);
            }
        }
    });
}

}  // namespace vqtex
