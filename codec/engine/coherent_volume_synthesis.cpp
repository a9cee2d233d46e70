// coherent_volume_synthesis.cpp - example-volume coordinates synthesised
// frame by frame with spatio-temporal coherent candidates (Wei & Levoy
// section 5.2's animated textures on the engine of Lefebvre & Hoppe 2005
// sections 3-4 and 2006 section 4; Ashikhmin 2001). See
// coherent_volume_synthesis.hpp.
#include "engine/coherent_volume_synthesis.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "common/error.hpp"
#include "dsp/dsp.hpp"
#include "engine/coherent_common.hpp"
#include "engine/pyramid.hpp"

namespace vqtex {
namespace {

using coherent::kRadius;
using coherent::kSide;
using coherent::kTaps;
using coherent::pixel_hash;

// Current, previous and next frame windows propose candidates.
constexpr int kMaxCandidates = 3 * kTaps;

// One level of the example as the correction reads it: per example frame,
// kAppearanceDims values per pixel (appearance vectors, or raw colours for
// the polish), with taps `spacing` apart.
struct VolumeLevelView {
    const AppearanceSpace& space;  // frame 0's: size and edges, shared by all frames
    std::vector<const int16_t*> planes;  // per example frame
    int spacing;
    const dsp::Kernels& kernels;
    int temporal_bias;  // VolumeCoherentOptions::temporal_bias

    int frames() const { return int(planes.size()); }
    const int16_t* feature(uint64_t v) const {
        return planes[std::size_t(voxel_t(v))] + (std::size_t(voxel_y(v)) * space.width + voxel_x(v)) * kAppearanceDims;
    }
    // One window's distance, stopping once it exceeds `bound`.
    uint64_t window(int frame, const int16_t* query, int x, int y, uint64_t bound) const {
        return coherent::window_distance(kernels, space, planes[std::size_t(frame)], spacing, query, x, y,
                                         uint32_t(std::min<uint64_t>(bound, UINT32_MAX)));
    }
};

// The frames around the one being corrected, as positions of the same
// level (nullptr when there is none).
struct Neighbours {
    const uint64_t* previous;
    const uint64_t* next;
    int gap;  // output frames from the current one to `next`
};

// The sources of the 5x5 window (wrapped columns xs, rows ys) of `map` (w wide).
void gather_sources(const uint64_t* map, int w, const int* xs, const int* ys, uint64_t* out) {
    for (int r = 0, t = 0; r < kSide; ++r) {
        const uint64_t* row = map + std::size_t(ys[r]) * w;
        for (int c = 0; c < kSide; ++c, ++t) out[t] = row[xs[c]];
    }
}

// One correction of voxel (x, y) of the current frame `cur`: the best of
// the coherent candidates its current, previous and next neighbours
// propose, by the distance of the current window plus the previous frame's
// window (against the candidate's example frame minus one) plus the next
// frame's (example frame plus `gap`).
uint64_t correct_voxel(const VolumeLevelView& v, const uint64_t* cur, const Neighbours& around, int w, const int* xs,
                       const int* ys) {
    const int frames = v.frames();
    uint64_t sources[kTaps], before[kTaps], after[kTaps];
    gather_sources(cur, w, xs, ys, sources);
    if (around.previous) gather_sources(around.previous, w, xs, ys, before);
    if (around.next) gather_sources(around.next, w, xs, ys, after);
    const uint64_t own = sources[kTaps / 2];
    const int ox = voxel_x(own), oy = voxel_y(own), ot = voxel_t(own);
    const int t_before = (ot + frames - 1) % frames, t_after = (ot + around.gap) % frames;
    {
        // Inside a coherent copy in space and time every candidate is the
        // voxel's own position: nothing to compare (most voxels).
        const int reach = kRadius * v.spacing;
        if (ox >= reach && oy >= reach && ox + reach < v.space.width && oy + reach < v.space.height) {
            uint64_t differ = 0;
            for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
                for (int dx = -kRadius; dx <= kRadius; ++dx, ++t) {
                    const int px = ox + dx * v.spacing, py = oy + dy * v.spacing;
                    differ |= sources[t] ^ pack_voxel(px, py, ot);
                    if (around.previous) differ |= before[t] ^ pack_voxel(px, py, t_before);
                    if (around.next) differ |= after[t] ^ pack_voxel(px, py, t_after);
                }
            if (differ == 0) return own;
        }
    }
    uint64_t candidates[kMaxCandidates];
    bool closes[kMaxCandidates];  // proposed by the next frame (loop closing)
    int count = 0;
    const int ex_w = v.space.width, ex_h = v.space.height;
    // A neighbour's source moved back by its offset (and to another frame by
    // `dt`), unless that leaves an example that does not tile.
    auto propose = [&](uint64_t source, int dx, int dy, int dt, bool from_next) {
        int ux = voxel_x(source) - dx * v.spacing, uy = voxel_y(source) - dy * v.spacing;
        if (v.space.wraps) {
            ux = Image::wrap(ux, ex_w);
            uy = Image::wrap(uy, ex_h);
        } else if (ux < 0 || uy < 0 || ux >= ex_w || uy >= ex_h) {
            return;
        }
        const uint64_t c = pack_voxel(ux, uy, (voxel_t(source) + dt + frames) % frames);
        if (c == own) return;
        for (int j = 0; j < count; ++j)
            if (candidates[j] == c) {
                closes[j] = closes[j] || from_next;
                return;
            }
        closes[count] = from_next;
        candidates[count++] = c;
    };
    for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
        for (int dx = -kRadius; dx <= kRadius; ++dx, ++t) {
            if (around.previous) propose(before[t], dx, dy, 1, false);
            propose(sources[t], dx, dy, 0, false);
            if (around.next) propose(after[t], dx, dy, -(around.gap % frames), true);
        }
    if (count == 0) return own;
    alignas(32) int16_t query[3][kTaps * kAppearanceDims];
    for (int t = 0; t < kTaps; ++t) {
        std::memcpy(query[0] + t * kAppearanceDims, v.feature(sources[t]), sizeof(int16_t) * kAppearanceDims);
        if (around.previous)
            std::memcpy(query[1] + t * kAppearanceDims, v.feature(before[t]), sizeof(int16_t) * kAppearanceDims);
        if (around.next)
            std::memcpy(query[2] + t * kAppearanceDims, v.feature(after[t]), sizeof(int16_t) * kAppearanceDims);
    }
    auto distance = [&](uint64_t c, uint64_t bound) {
        const int cx = voxel_x(c), cy = voxel_y(c), ct = voxel_t(c);
        uint64_t d = v.window(ct, query[0], cx, cy, bound);
        if (around.previous && d <= bound) d += v.window((ct + frames - 1) % frames, query[1], cx, cy, bound - d);
        if (around.next && d <= bound) d += v.window((ct + around.gap) % frames, query[2], cx, cy, bound - d);
        return d;
    };
    // The voxel's own position first; ties go to the earlier candidate.
    uint64_t best = own;
    uint64_t best_d = distance(own, UINT64_MAX);
    for (int i = 0; i < count; ++i) {
        // After the first frame the voxel's own position continues the
        // previous frame's motion: another must beat it by the bias, d (1 +
        // bias/256) < best, unless it leads to the first frame (closing).
        const uint64_t bias = around.previous && !closes[i] ? uint64_t(v.temporal_bias) : 0;
        const uint64_t bound = (best_d * 256) / (256 + bias);
        uint64_t d = distance(candidates[i], bound);
        d += (d * bias) / 256;
        if (d < best_d) {
            best_d = d;
            best = candidates[i];
        }
    }
    return best;
}

void correction_pass(const VolumeLevelView& view, VoxelMap& map, const Neighbours& around, int threads) {
    const int w = map.width;
    coherent::interleaved_pass(threads, map.width, map.height, map.voxels, [&](int, int, const int* xs, const int* ys) {
        return correct_voxel(view, map.voxels.data(), around, w, xs, ys);
    });
}

VoxelMap upsample(const AppearanceSpace& space, const VoxelMap& parent, int width, int height, int spacing) {
    VoxelMap out{width, height, std::vector<uint64_t>(std::size_t(width) * height)};
    // Animations keep the edges of formats 3 to 6 (no edge guard: the
    // clamp was measured on still textures only).
    const bool clamp = false;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint64_t p = parent.voxels[std::size_t(y >> 1) * parent.width + (x >> 1)];
            out.voxels[std::size_t(y) * width + x] =
                pack_voxel(coherent::child_coordinate(space.width, space.wraps, voxel_x(p), x & 1, spacing, clamp),
                           coherent::child_coordinate(space.height, space.wraps, voxel_y(p), y & 1, spacing, clamp),
                           voxel_t(p));
        }
    return out;
}

// The previous frame's positions one example frame later: inside every
// coherent copy this is exactly the example's motion.
VoxelMap advanced(const VoxelMap& previous, int frames) {
    VoxelMap out = previous;
    for (uint64_t& v : out.voxels) v = pack_voxel(voxel_x(v), voxel_y(v), (voxel_t(v) + 1) % frames);
    return out;
}

}  // namespace

Volume synthesize_volume_coherent(const std::vector<AppearanceSpace>& example, const std::vector<Image>& frames,
                                  const VolumeCoherentOptions& options, std::vector<VoxelMap>* maps) {
    const AppearanceSpace& space = example[0];
    const int example_frames = int(example.size());
    const int top = int(space.levels.size()) - 1;
    const int out_frames = options.frames;
    auto level_view = [&](int l) {
        VolumeLevelView view{space, {}, space.levels[std::size_t(l)].spacing, dsp::kernels(), options.temporal_bias};
        for (const AppearanceSpace& f : example) view.planes.push_back(f.levels[std::size_t(l)].features.data());
        return view;
    };
    VolumeLevelView polish{space, {}, 1, dsp::kernels(), options.temporal_bias};
    for (const AppearanceSpace& f : example) polish.planes.push_back(f.pixels.data());

    auto level_area = [&](int l) {
        return uint64_t(pyramid_level_size(options.width, l)) * uint64_t(pyramid_level_size(options.height, l));
    };
    uint64_t total = 0, done = 0;
    for (int l = top; l >= 0; --l) {
        const uint64_t first = level_area(l) * uint64_t(l == top ? options.coarse_passes : options.passes);
        const uint64_t later = options.frame_levels == FrameLevels::All || l == 0 ? level_area(l) * uint64_t(options.passes) : 0;
        total += first + later * uint64_t(out_frames - 1);
    }
    auto report = [&](uint64_t work) {
        done += work;
        if (options.progress && !options.progress(done, total))
            fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    };

    Volume out(options.width, options.height, out_frames, frames[0].channels);
    if (maps) maps->assign(std::size_t(out_frames), VoxelMap{});
    std::vector<VoxelMap> first(std::size_t(top + 1)), previous(std::size_t(top + 1)), current(std::size_t(top + 1));
    for (int f = 0; f < out_frames; ++f) {
        // The last frame of a loop is followed by the first: the last
        // closing_frames frames are also compared with the first frame's
        // positions that many frames ahead (pure advection), so that seams
        // that moved during the loop move back over several frames rather
        // than at the wrap.
        const int gap = out_frames - f;
        const bool closing = options.close_loop && out_frames > 1 && f > 0 && gap <= options.closing_frames;
        const int lowest = f == 0 || options.frame_levels == FrameLevels::All ? top : 0;
        for (int l = lowest; l >= 0; --l) {
            const int w = pyramid_level_size(options.width, l), h = pyramid_level_size(options.height, l);
            const int spacing = space.levels[std::size_t(l)].spacing;
            VoxelMap map;
            if (f == 0 && l == top) {
                // The coarsest level starts anywhere: positions drawn at random
                // in x, y and t.
                map = VoxelMap{w, h, std::vector<uint64_t>(std::size_t(w) * h)};
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        const uint64_t r = pixel_hash(options.seed, l, 0, x, y);
                        const uint64_t rt = pixel_hash(options.seed, l, 2, x, y);
                        map.voxels[std::size_t(y) * w + x] =
                            pack_voxel(int((r & 0xFFFFFFFF) % uint64_t(space.width)),
                                       int((r >> 32) % uint64_t(space.height)), int(rt % uint64_t(example_frames)));
                    }
            } else if (f > 0 && l == lowest) {
                map = advanced(previous[std::size_t(l)], example_frames);
            } else {
                map = upsample(space, current[std::size_t(l + 1)], w, h, spacing);
            }
            const Neighbours around{f > 0 ? previous[std::size_t(l)].voxels.data() : nullptr,
                                    closing ? first[std::size_t(l)].voxels.data() : nullptr, gap};
            const VolumeLevelView view = level_view(l);
            const int passes = f == 0 && l == top ? options.coarse_passes : options.passes;
            for (int pass = 0; pass < passes; ++pass) {
                correction_pass(view, map, around, options.threads);
                report(uint64_t(w) * uint64_t(h));
            }
            if (l == 0)
                for (int pass = 0; pass < options.polish_passes; ++pass)
                    correction_pass(polish, map, around, options.threads);
            current[std::size_t(l)] = std::move(map);
        }
        const VoxelMap& finest = current[0];
        for (int y = 0; y < options.height; ++y)
            for (int x = 0; x < options.width; ++x) {
                const uint64_t v = finest.voxels[std::size_t(y) * options.width + x];
                copy_pixel(out.at(x, y, f), frames[std::size_t(voxel_t(v))].at(voxel_x(v), voxel_y(v)), out.channels);
            }
        if (maps) (*maps)[std::size_t(f)] = finest;
        if (f == 0) first = current;
        previous.swap(current);
    }
    if (options.roll) {
        // One cut for all frames (coherent::torus_origin), where the pixels
        // change least summed over the frames: cut per frame, the motion
        // would jump.
        auto step = [&](int x0, int y0, int x1, int y1) {
            int d = 0;
            for (int f = 0; f < out_frames; ++f) {
                const uint8_t* a = out.at(x0, y0, f);
                const uint8_t* b = out.at(x1, y1, f);
                for (int c = 0; c < out.channels; ++c) d += std::abs(int(a[c]) - int(b[c]));
            }
            return int64_t(d);
        };
        const std::pair<int, int> origin = coherent::torus_origin(options.width, options.height, step, options.threads);
        if (origin.first || origin.second) {
            Volume rolled(out.width, out.height, out.frames, out.channels);
            for (int f = 0; f < out_frames; ++f)
                for (int y = 0; y < out.height; ++y)
                    for (int x = 0; x < out.width; ++x)
                        copy_pixel(rolled.at(x, y, f),
                                   out.at(Image::wrap(x + origin.first, out.width),
                                          Image::wrap(y + origin.second, out.height), f),
                                   out.channels);
            out = std::move(rolled);
        }
    }
    return out;
}

}  // namespace vqtex
