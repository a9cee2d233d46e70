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
#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "format/animation_file.hpp"
#include "format/atlas_file.hpp"
#include "writer/animation_writer.hpp"
#include "writer/atlas_encoder.hpp"
#include "metrics.hpp"

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

}  // namespace

double budgeted_frames(int frames) { return 1.0 + double(std::clamp(frames, 1, kMaxChosenFrames) - 1) / 5.0; }

uint64_t animation_budget_of_quality(int quality, uint64_t pixels, int frames) {
    const uint64_t still = atlas_budget_of_quality(quality, std::min<uint64_t>(pixels, kBudgetedPixels));
    return uint64_t(std::llround(double(still) * budgeted_frames(frames)));
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

namespace {

// Budgets up to this many bytes per effective example pixel (the frame's
// area times budgeted_frames) also try parts of the frame area: the stills' threshold
// (atlas_choice.cpp), below which a smaller area coded finer can win.
constexpr double kPartBytesPerPixel = 0.13;

// The proxy decode: this many frames, at twice the atlas's side up to
// kProxySide, scored on every second frame after the first (the first is
// a still synthesis; the later ones are what the motion makes of it).
constexpr int kProxyFrames = 8;
constexpr int kProxySide = 256;

struct Region {
    int x = 0, y = 0, width = 0, height = 0;
};

struct ProxyScores {
    double completeness = 0, swd = 0, coherence = 0;
};

struct Candidate {
    Region region;
    int frames = 0;
    int levels = 0;
    int cq = -1;
    std::vector<uint8_t> file;
    uint32_t attempts = 0;
    ProxyScores scores;
};

// The finest AV1 level at which the candidate's file fits the budget
// (file stays empty when even 63 does not).
void code_candidate(const std::vector<Image>& frames, const AnimationChoiceOptions& options, uint64_t budget,
                    Candidate& c) {
    const Image& first = frames[0];
    const Region& r = c.region;
    std::vector<Image> atlas;
    for (int t = 0; t < c.frames; ++t) atlas.push_back(frames[std::size_t(t)].crop(r.x, r.y, r.width, r.height));
    const int max_levels = coherent_levels(r.width, r.height);
    c.levels = options.levels ? std::min(options.levels, max_levels) : max_levels;
    FileHeader h;
    h.version = kCutAnimationFormatVersion;
    h.channels = uint8_t(first.channels);
    h.levels = uint8_t(c.levels);
    h.exemplar_width = uint32_t(first.width);
    h.exemplar_height = uint32_t(first.height);
    h.seed = options.seed;
    AnimationParams params;
    params.example_tileable = options.example_tileable && r.width == first.width && r.height == first.height;
    std::map<int, std::vector<uint8_t>> files;
    const auto file_at = [&](int cq) -> const std::vector<uint8_t>& {
        auto it = files.find(cq);
        if (it != files.end()) return it->second;
        AtlasEncodeOptions o;
        o.cq_level = cq;
        o.speed = kSequenceSpeed;
        ++c.attempts;
        return files[cq] = encode_animation_file(h, r.width, r.height, c.frames, encode_atlas_frames(atlas, o), params);
    };
    c.cq = finest_fitting_level(budget, [&](int q) { return file_at(q).size(); });
    if (c.cq >= 0) c.file = file_at(c.cq);
}

// What the encoder can measure of a file: a few frames of the animation
// the decoder makes from it (a seed of its own), each against the example
// frame of the same index.
ProxyScores proxy_scores(const std::vector<vqtex_metrics::Image>& reference, const std::vector<uint8_t>& file) {
    const AnimationFile f = decode_animation_file(file.data(), file.size(), std::size_t(1) << 32);
    AnimationRequest request;
    request.width = std::min(2 * int(f.header.exemplar_width), kProxySide);
    request.height = std::min(2 * int(f.header.exemplar_height), kProxySide);
    request.frames = kProxyFrames;
    request.seed = 2;
    const Volume out = synthesize_animation(f, request);
    ProxyScores s;
    int scored = 0;
    for (int t = 1; t < out.frames; t += 2, ++scored) {
        const Image frame = out.frame(t);
        const vqtex_metrics::Image texture = as_metrics_image(frame);
        const vqtex_metrics::Image& ref = reference[std::size_t(t) % reference.size()];
        s.completeness += vqtex_metrics::completeness(ref, texture, 7, 256, vqtex_metrics::kDefaultSeed);
        s.swd += vqtex_metrics::sliced_wasserstein(texture, ref).mean;
        s.coherence += vqtex_metrics::coherence(texture, ref, 7, 256, vqtex_metrics::kDefaultSeed);
    }
    s.completeness /= scored;
    s.swd /= scored;
    s.coherence /= scored;
    return s;
}

}  // namespace

AnimationChoice choose_animation_atlas(const std::vector<Image>& frames, const AnimationChoiceOptions& options) {
    if (frames.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "an animation needs at least one frame");
    const Image& first = frames[0];
    if (first.width < kMinAtlasSide || first.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an animation's frames must be at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) +
                                              " pixels to store as an atlas: store it as trees (--trees)");
    // The whole frame area, or above 256x256 the square part of side 256
    // that looks most like the whole.
    Region area{0, 0, first.width, first.height};
    if (uint64_t(area.width) * uint64_t(area.height) > kBudgetedPixels) {
        const int side = std::min({area.width, area.height, 256});
        const auto at = representative_place(first, side);
        area = Region{at[0], at[1], side, side};
    }
    const int length = loop_length(frames);
    const uint64_t pixels = uint64_t(area.width) * uint64_t(area.height);
    const uint64_t budget = options.budget ? options.budget : animation_budget_of_quality(options.quality, pixels, length);
    const auto chosen = [&](Candidate& c) {
        AnimationChoice out;
        out.file = std::move(c.file);
        out.cq = c.cq;
        out.levels = c.levels;
        out.x = c.region.x;
        out.y = c.region.y;
        out.width = c.region.width;
        out.height = c.region.height;
        out.frames = c.frames;
        return out;
    };
    uint32_t attempts = 0;
    Candidate whole;
    whole.region = area;
    whole.frames = length;
    code_candidate(frames, options, budget, whole);
    attempts += whole.attempts;
    const double effective_pixels = double(pixels) * budgeted_frames(length);
    if (!whole.file.empty() &&
        (double(budget) > kPartBytesPerPixel * effective_pixels || std::min(area.width, area.height) < 4 * kMinAtlasSide)) {
        AnimationChoice c = chosen(whole);
        c.attempts = attempts;
        return c;
    }
    if (!whole.file.empty()) {
        // A smaller part of the frames coded more finely is sharper but
        // has less variety. As for stills, the parts whose animation finds
        // the example's windows as well as the whole's does (completeness)
        // compete with it on SWD and coherence, each relative to the
        // whole's: centre and top-left parts of 3/4 and 1/2 the side.
        std::vector<Candidate> parts;
        for (const int num : {3, 2}) {
            const int w = area.width * num / 4, h = area.height * num / 4;
            for (const bool centre : {true, false}) {
                Candidate c;
                c.region = Region{area.x + (centre ? (area.width - w) / 2 : 0),
                                  area.y + (centre ? (area.height - h) / 2 : 0), w, h};
                c.frames = length;
                parts.push_back(std::move(c));
            }
        }
        std::vector<vqtex_metrics::Image> reference;
        for (int t = 0; t < std::min<int>(int(frames.size()), kProxyFrames); ++t)
            reference.push_back(as_metrics_image(frames[std::size_t(t)].crop(area.x, area.y, area.width, area.height)));
        parallel_for(options.threads, parts.size() + 1, 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                Candidate& c = i == parts.size() ? whole : parts[i];
                if (i < parts.size()) code_candidate(frames, options, budget, c);
                if (!c.file.empty()) c.scores = proxy_scores(reference, c.file);
            }
        });
        Candidate* best = &whole;
        double best_score = 2.0;  // the whole's: 1 + 1
        for (Candidate& c : parts) {
            attempts += c.attempts;
            if (c.file.empty() || c.scores.completeness > whole.scores.completeness) continue;
            const double score = c.scores.swd / std::max(whole.scores.swd, 1e-9) +
                                 c.scores.coherence / std::max(whole.scores.coherence, 1e-9);
            if (score < best_score) {
                best_score = score;
                best = &c;
            }
        }
        AnimationChoice c = chosen(*best);
        c.attempts = attempts;
        return c;
    }
    // Nothing fits: fewer frames first (the loop then closes less well),
    // then a smaller area.
    Candidate c;
    c.region = area;
    c.frames = length;
    for (;;) {
        if (c.frames > 8) {
            c.frames /= 2;
        } else if (std::min(c.region.width, c.region.height) / 2 >= 32) {
            c.region = Region{c.region.x + c.region.width / 4, c.region.y + c.region.height / 4, c.region.width / 2,
                              c.region.height / 2};
        } else {
            fail(VQTEX_ERROR_LIMIT_EXCEEDED, "no space-time atlas of this animation fits " + std::to_string(budget) +
                                                 " bytes: ask for a larger target size");
        }
        c.attempts = 0;
        code_candidate(frames, options, budget, c);
        attempts += c.attempts;
        if (!c.file.empty()) {
            AnimationChoice out = chosen(c);
            out.attempts = attempts;
            return out;
        }
    }
}

}  // namespace vqtex
