// animation_choice.cpp - choosing an animation's space-time atlas and its
// AV1 level for a byte budget (docs/ANIMATION.md "The space-time atlas").
#include "analysis/animation_choice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>

#include "analysis/atlas_choice.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_file.hpp"
#include "writer/animation_writer.hpp"
#include "writer/atlas_encoder.hpp"

namespace vqtex {

namespace {

// libaom's speed for the sequences: the level search's files and the one
// kept are made alike, so the kept file is the one measured.
constexpr int kSequenceSpeed = 6;

// Longest atlas the encoder writes: a loop of a few seconds is the texture;
// beyond it frames cost bytes without adding variety.
constexpr int kMaxChosenFrames = 64;

double mean_absolute_difference(const Image& a, const Image& b) {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += uint64_t(std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    return double(sum) / double(std::max<std::size_t>(1, a.pixels.size()));
}

Image crop(const Image& image, int x, int y, int w, int h) {
    if (x == 0 && y == 0 && w == image.width && h == image.height) return image;
    Image out(w, h, image.channels);
    for (int row = 0; row < h; ++row)
        std::copy_n(image.at(x, y + row), std::size_t(w) * std::size_t(image.channels), out.at(0, row));
    return out;
}

}  // namespace

uint64_t animation_budget_of_quality(int quality, uint64_t pixels, int frames) {
    const uint64_t still = atlas_budget_of_quality(quality, std::min<uint64_t>(pixels, kBudgetedPixels));
    const int counted = std::clamp(frames, 1, kMaxChosenFrames);
    return still + still * uint64_t(counted - 1) / 4;
}

int loop_length(const std::vector<Image>& frames) {
    const int n = int(frames.size());
    if (n <= 2) return n;
    // The typical change: the median of the steps between consecutive frames.
    std::vector<double> steps;
    for (int t = 0; t + 1 < n; ++t) steps.push_back(mean_absolute_difference(frames[std::size_t(t)], frames[std::size_t(t) + 1]));
    std::nth_element(steps.begin(), steps.begin() + std::ptrdiff_t(steps.size() / 2), steps.end());
    const double step = std::max(steps[steps.size() / 2], 1e-3);
    // Closing after n frames shows frame n - 1 followed by frame 0. The
    // whole loop's closure is the step from its last frame to its first,
    // less a typical step; a segment's is frame 0 against frame n, the
    // frame the example shows after frame n - 1.
    std::vector<double> gap(std::size_t(n) + 1, 0.0);
    for (int len = 2; len <= std::min(n, kMaxChosenFrames); ++len)
        gap[std::size_t(len)] = len == n ? std::max(0.0, mean_absolute_difference(frames.back(), frames[0]) - step)
                                         : mean_absolute_difference(frames[std::size_t(len)], frames[0]);
    double best = gap[2];
    for (int len = 2; len <= std::min(n, kMaxChosenFrames); ++len) best = std::min(best, gap[std::size_t(len)]);
    for (int len = std::min(n, kMaxChosenFrames); len >= 2; --len)
        if (gap[std::size_t(len)] <= best + 0.25 * step) return len;
    return 2;
}

AnimationChoice choose_animation_atlas(const std::vector<Image>& frames, const AnimationChoiceOptions& options) {
    if (frames.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "an animation needs at least one frame");
    const Image& first = frames[0];
    AnimationChoice c;
    c.width = first.width;
    c.height = first.height;
    if (uint64_t(c.width) * uint64_t(c.height) > kBudgetedPixels) {
        const int side = std::min({c.width, c.height, 256});
        if (c.width > side || c.height > side) {
            const auto at = representative_place(first, side);
            c.x = at[0];
            c.y = at[1];
        }
        c.width = c.height = side;
    }
    c.frames = loop_length(frames);
    if (c.width < kMinAtlasSide || c.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an animation's frames must be at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) +
                                              " pixels to store as an atlas: store it as trees (--trees)");
    const uint64_t budget = options.budget ? options.budget
                                           : animation_budget_of_quality(options.quality,
                                                                         uint64_t(c.width) * uint64_t(c.height), c.frames);
    for (;;) {
        std::vector<Image> atlas;
        for (int t = 0; t < c.frames; ++t) atlas.push_back(crop(frames[std::size_t(c.first + t)], c.x, c.y, c.width, c.height));
        const int max_levels = coherent_levels(c.width, c.height);
        c.levels = options.levels ? std::min(options.levels, max_levels) : max_levels;
        FileHeader h;
        h.version = kAnimationAtlasFormatVersion;
        h.channels = uint8_t(first.channels);
        h.levels = uint8_t(c.levels);
        h.exemplar_width = uint32_t(first.width);
        h.exemplar_height = uint32_t(first.height);
        h.seed = options.seed;
        AnimationParams params;
        params.example_tileable = options.example_tileable && c.width == first.width && c.height == first.height;
        std::map<int, std::vector<uint8_t>> files;
        const auto file_at = [&](int cq) -> const std::vector<uint8_t>& {
            auto it = files.find(cq);
            if (it != files.end()) return it->second;
            AtlasEncodeOptions o;
            o.cq_level = cq;
            o.speed = kSequenceSpeed;
            ++c.attempts;
            return files[cq] = encode_animation_file(h, c.width, c.height, c.frames, encode_atlas_frames(atlas, o), params);
        };
        const int cq = finest_fitting_level(budget, [&](int q) { return file_at(q).size(); });
        if (cq >= 0) {
            c.cq = cq;
            c.file = file_at(cq);
            return c;
        }
        // Nothing fits: fewer frames first (the loop then closes less
        // well), then a smaller area.
        if (c.frames > 8) {
            c.frames /= 2;
        } else if (std::min(c.width, c.height) / 2 >= 32) {
            c.x += c.width / 4;
            c.y += c.height / 4;
            c.width /= 2;
            c.height /= 2;
        } else {
            fail(VQTEX_ERROR_LIMIT_EXCEEDED, "no space-time atlas of this animation fits " + std::to_string(budget) +
                                                 " bytes: ask for a larger target size");
        }
    }
}

}  // namespace vqtex
