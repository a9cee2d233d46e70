// known_pyramid.cpp - the known pixels of a hole-filling pyramid and the
// coarse context values (paper section 5.1; see known_pyramid.hpp).
#include "fill/known_pyramid.hpp"

#include <algorithm>

#include "engine/pyramid.hpp"

namespace vqtex::constrained {

// Context pyramid of the target: which pixels of each coarser level are
// usable as context, and with which values. A coarser pixel is usable when
// at least `threshold`/256 of its filter weight falls on usable finer pixels;
// its value is then the filter over those pixels alone, renormalised
// (normalised convolution). With the strict rule of known_pyramid, which
// wants the whole footprint, holes grow by about two pixels per level, and
// the ring they grow by is synthesised at the coarse level although the
// finer level knows most of it: the coarse context of the finer level's
// boundary pixels then disagrees with their known neighbours and the fill
// meets them with a step (a visible seam). A wholly known footprint gives
// exactly the pyramid's value, so strict pixels are unchanged.
std::vector<KnownLevel> context_known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels,
                                              int threshold) {
    std::vector<KnownLevel> out(static_cast<std::size_t>(levels));
    out[0].width = width;
    out[0].height = height;
    out[0].known = known0;
    out[0].build_sums();
    for (int l = 1; l < levels; ++l) {
        const KnownLevel& fine = out[std::size_t(l - 1)];
        KnownLevel& k = out[std::size_t(l)];
        k.width = pyramid_level_size(width, l);
        k.height = pyramid_level_size(height, l);
        k.known.assign(std::size_t(k.width) * std::size_t(k.height), 0);
        for (int y = 0; y < k.height; ++y)
            for (int x = 0; x < k.width; ++x) {
                int weight = 0;
                for (int t = 0; t < 5; ++t)
                    for (int s = 0; s < 5; ++s)
                        if (fine.is_known(reflect_index(2 * x + s - 2, fine.width), reflect_index(2 * y + t - 2, fine.height)))
                            weight += kPyramidTaps[t] * kPyramidTaps[s];
                k.known[std::size_t(y) * std::size_t(k.width) + std::size_t(x)] = weight >= threshold ? 1 : 0;
            }
        k.build_sums();
    }
    return out;
}

// Known pixels for example windows: a coarser pixel counts only when its
// whole filter footprint is known (all 256/256 of the weight).
std::vector<KnownLevel> known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels) {
    return context_known_pyramid(width, height, known0, levels, 256);
}

// The values of context_known_pyramid: every usable pixel of each coarser
// level recomputed from the usable pixels of the level below (exact integer
// arithmetic; a wholly known footprint gives the pyramid's own value).
void apply_context_values(std::vector<Image>& pyramid, const std::vector<KnownLevel>& known) {
    for (std::size_t l = 1; l < pyramid.size(); ++l) {
        const Image& fine = pyramid[l - 1];
        const KnownLevel& fk = known[l - 1];
        Image& img = pyramid[l];
        const int c = img.channels;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                if (!known[l].is_known(x, y)) continue;
                uint32_t sum[kMaxChannels] = {}, weight = 0;
                for (int t = 0; t < 5; ++t)
                    for (int s = 0; s < 5; ++s) {
                        const int fx = reflect_index(2 * x + s - 2, fine.width), fy = reflect_index(2 * y + t - 2, fine.height);
                        if (!fk.is_known(fx, fy)) continue;
                        const uint32_t w = uint32_t(kPyramidTaps[t] * kPyramidTaps[s]);
                        weight += w;
                        for (int ch = 0; ch < c; ++ch) sum[ch] += w * fine.at(fx, fy)[ch];
                    }
                for (int ch = 0; ch < c; ++ch) img.at(x, y)[ch] = uint8_t((sum[ch] + weight / 2) / weight);
            }
    }
}

}  // namespace vqtex::constrained
