// coherent_volume_synthesis.cpp - example-volume coordinates synthesised
// frame by frame with spatio-temporal coherent candidates (Wei & Levoy
// section 5.2's animated textures on the engine of Lefebvre & Hoppe 2005
// sections 3-4 and 2006 section 4; Ashikhmin 2001). See
// coherent_volume_synthesis.hpp.
#include "engine/coherent_volume_synthesis.hpp"

#include <algorithm>
#include <cstring>

#include "dsp/dsp.hpp"
#include "engine/coherent_correction.hpp"
#include "engine/coherent_progress.hpp"
#include "engine/coherent_start.hpp"
#include "engine/coherent_torus.hpp"
#include "engine/pyramid.hpp"
#include "engine/seam_blend.hpp"
#include "engine/seam_cut.hpp"

namespace vqtex {
namespace {

using coherent::kTaps;
// The four nearest taps of a window: up, left, right, down.
constexpr int kNearest[4] = {kTaps / 2 - coherent::kSide, kTaps / 2 - 1, kTaps / 2 + 1, kTaps / 2 + coherent::kSide};
// The still engine's rules against stutters and small copies
// (coherent_pixel_correction.cpp), with its link bias: a voxel that one of
// the four nearest neighbours holds is neither offered nor kept, and a
// candidate's distance is surcharged by kLinkBias/256 per nearest
// neighbour that does not continue its copy. Measured (docs/ANIMATION.md):
// on panning photographs, per-frame SWD 11-14% and coherence 6-8% lower
// against all the example's frames, and the rows of repeated pixels gone;
// on the corpus's synthetic animations within seed-to-seed variation.
constexpr uint64_t kLinkBias = 256;

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

// The animation's correction step (coherent::correct): a voxel of the
// current frame `cur` (w wide) takes the best of the coherent candidates
// its current, previous and next neighbours propose, by the distance of
// the current window plus the previous frame's window (against the
// candidate's example frame minus one) plus the next frame's (example frame
// plus `gap`), surcharged per nearest neighbour that does not continue the
// candidate's copy (the link bias). After the first frame the voxel's own
// position continues the previous frame's motion: another must beat it by
// the temporal bias, unless it leads to the first frame (closing the loop).
struct VoxelStep {
    using Position = uint64_t;
    using Distance = uint64_t;
    // Current, previous and next frame windows propose candidates.
    static constexpr int kMaxCandidates = 3 * kTaps;
    static constexpr int kWindows = 3;
    struct Window {
        uint64_t sources[kTaps], before[kTaps], after[kTaps];
        uint64_t own() const { return sources[kTaps / 2]; }
    };

    const VolumeLevelView& v;
    const uint64_t* cur;
    const Neighbours& around;
    int w;

    void gather(const int* xs, const int* ys, Window& win) const {
        coherent::gather_window(cur, w, xs, ys, win.sources);
        if (around.previous) coherent::gather_window(around.previous, w, xs, ys, win.before);
        if (around.next) coherent::gather_window(around.next, w, xs, ys, win.after);
    }
    // Inside a coherent copy in space and time every candidate is the
    // voxel's own position: nothing to compare (most voxels).
    bool settled(const Window& win, uint32_t&) const {
        const uint64_t own = win.own();
        const int ox = voxel_x(own), oy = voxel_y(own), ot = voxel_t(own), frames = v.frames();
        const uint64_t* windows[3] = {win.sources};
        uint64_t centres[3] = {own};
        int count = 1;
        if (around.previous) {
            windows[count] = win.before;
            centres[count++] = pack_voxel(ox, oy, (ot + frames - 1) % frames);
        }
        if (around.next) {
            windows[count] = win.after;
            centres[count++] = pack_voxel(ox, oy, (ot + around.gap) % frames);
        }
        return coherent::continue_copy<coherent::VoxelPositions>(v.space, v.spacing, windows, centres, count);
    }
    // A neighbour's source moved back by its offset (and to another frame by
    // `dt`), unless that leaves an example that does not tile; flagged when
    // the next frame proposes it (loop closing).
    template <typename List>
    void propose(const Window& win, uint32_t, List& candidates) const {
        const int frames = v.frames();
        const uint64_t own = win.own();
        const auto offer = [&](uint64_t source, int t, int dt, bool from_next) {
            int ux, uy;
            if (!coherent::continued_source(v.space, v.spacing, voxel_x(source), voxel_y(source), t, ux, uy)) return;
            const uint64_t c = pack_voxel(ux, uy, (voxel_t(source) + dt + frames) % frames);
            if (c != own && !barred(win, c)) candidates.add(c, from_next);
        };
        for (int t = 0; t < kTaps; ++t) {
            if (around.previous) offer(win.before[t], t, 1, false);
            offer(win.sources[t], t, 0, false);
            if (around.next) offer(win.after[t], t, -(around.gap % frames), true);
        }
    }
    void fill_query(const Window& win, int16_t* query) const {
        const auto feature = [&](uint64_t p) { return v.feature(p); };
        coherent::fill_query(win.sources, feature, query);
        if (around.previous) coherent::fill_query(win.before, feature, query + kTaps * kAppearanceDims);
        if (around.next) coherent::fill_query(win.after, feature, query + 2 * kTaps * kAppearanceDims);
    }
    // No two adjacent pixels of an example frame share a voxel: a
    // candidate that one of the four nearest neighbours holds would repeat
    // a pixel beside itself (a stutter of rows or columns), as the still
    // engine's rule says (coherent_pixel_correction.cpp); the own voxel
    // gives way to any candidate when it does.
    bool barred(const Window& win, uint64_t c) const {
        for (int n : kNearest)
            if (c == win.sources[n]) return true;
        return false;
    }
    uint64_t weight(const Window& win, uint64_t c, bool closes) const {
        const int cx = voxel_x(c), cy = voxel_y(c), ct = voxel_t(c), s = v.spacing;
        int links = 0;
        for (int n : kNearest)
            links += int(win.sources[n] == pack_voxel(cx + coherent::tap_dx(n) * s, cy + coherent::tap_dy(n) * s, ct));
        return (256 + kLinkBias * uint64_t(4 - links)) *
               (256 + (around.previous && !closes ? uint64_t(v.temporal_bias) : 0));
    }
    uint64_t distance(const Window&, const int16_t* query, uint64_t c, uint64_t bound) const {
        const int cx = voxel_x(c), cy = voxel_y(c), ct = voxel_t(c), frames = v.frames();
        uint64_t d = v.window(ct, query, cx, cy, bound);
        if (around.previous && d <= bound)
            d += v.window((ct + frames - 1) % frames, query + kTaps * kAppearanceDims, cx, cy, bound - d);
        if (around.next && d <= bound)
            d += v.window((ct + around.gap) % frames, query + 2 * kTaps * kAppearanceDims, cx, cy, bound - d);
        return d;
    }
};

void correction_pass(const VolumeLevelView& view, VoxelMap& map, const Neighbours& around, int threads) {
    coherent::correction_pass(threads, map.width, map.height, map.voxels,
                              VoxelStep{view, map.voxels.data(), around, map.width});
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

    coherent::PassProgress progress{options.progress};
    for (int l = top; l >= 0; --l) {
        const uint64_t area = coherent::level_area(options.width, options.height, l);
        const uint64_t first = area * uint64_t(l == top ? options.coarse_passes : options.passes);
        const uint64_t later = options.frame_levels == FrameLevels::All || l == 0 ? area * uint64_t(options.passes) : 0;
        progress.total += first + later * uint64_t(out_frames - 1);
    }
    const coherent::StartRules upsampling{options.seed, 0, options.clamp_children, options.threads};

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
            if (f > 0 && l == lowest) {
                map = advanced(previous[std::size_t(l)], example_frames);
            } else {
                map = VoxelMap{w, h, std::vector<uint64_t>(std::size_t(w) * h)};
                if (f == 0 && l == top) {
                    // The coarsest level starts anywhere: positions drawn at
                    // random in x, y and t.
                    coherent::random_start<coherent::VoxelPositions>(space, example_frames, options.seed, l, w, h,
                                                                     map.voxels.data());
                } else {
                    const VoxelMap& parent = current[std::size_t(l + 1)];
                    coherent::start_rows<coherent::VoxelPositions>(
                        space, [&](std::size_t i) { return parent.voxels[i]; }, parent.width, w, h, l, spacing,
                        upsampling, false, 0, h, map.voxels.data());
                }
            }
            const Neighbours around{f > 0 ? previous[std::size_t(l)].voxels.data() : nullptr,
                                    closing ? first[std::size_t(l)].voxels.data() : nullptr, gap};
            const VolumeLevelView view = level_view(l);
            const int passes = f == 0 && l == top ? options.coarse_passes : options.passes;
            for (int pass = 0; pass < passes; ++pass) {
                correction_pass(view, map, around, options.threads);
                progress.add(uint64_t(w) * uint64_t(h));
            }
            if (l == 0)
                for (int pass = 0; pass < options.polish_passes; ++pass)
                    correction_pass(polish, map, around, options.threads);
            current[std::size_t(l)] = std::move(map);
        }
        if (options.cut > 0) {
            CutRules rules;
            rules.reach = options.cut;
            cut_frame_seams(frames, space.wraps, options.width, options.height, current[0].voxels, rules,
                            options.threads);
        }
        const VoxelMap& finest = current[0];
        if (options.blend > 0) {
            Image frame(options.width, options.height, out.channels);
            blend_voxels(frames, space.wraps, options.blend, finest.voxels.data(), frame, options.threads);
            std::copy(frame.pixels.begin(), frame.pixels.end(), out.frame_data(f));
        } else {
            for (int y = 0; y < options.height; ++y)
                for (int x = 0; x < options.width; ++x) {
                    const uint64_t v = finest.voxels[std::size_t(y) * options.width + x];
                    copy_pixel(out.at(x, y, f), frames[std::size_t(voxel_t(v))].at(voxel_x(v), voxel_y(v)),
                               out.channels);
                }
        }
        if (maps) (*maps)[std::size_t(f)] = finest;
        if (f == 0) first = current;
        previous.swap(current);
    }
    if (options.roll) {
        // One cut for all frames, where the pixels change least summed over
        // the frames.
        std::vector<uint8_t*> planes;
        for (int f = 0; f < out_frames; ++f) planes.push_back(out.frame_data(f));
        coherent::cut_torus(planes, out.width, out.height, out.channels, options.threads);
    }
    return out;
}

}  // namespace vqtex
