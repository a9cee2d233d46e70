// The measures of an animation against its example (see anim_stats.hpp).
#include "anim_stats.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace vqtex_tools {
namespace {

double mean_abs_difference(const vqtex_metrics::Image& a, const vqtex_metrics::Image& b) {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += uint64_t(std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    return a.pixels.empty() ? 0.0 : double(sum) / double(a.pixels.size());
}

// `frames` side by side, up to 8 a row: the reference an output frame's
// windows are looked up in. A window across two frames is not the
// example's, but they are a few columns in a frame's width.
vqtex_metrics::Image mosaic(const Frames& frames) {
    const int w = frames[0].width, h = frames[0].height, c = frames[0].channels;
    const int n = int(frames.size()), cols = std::min(n, 8), rows = (n + cols - 1) / cols;
    vqtex_metrics::Image out;
    out.width = cols * w;
    out.height = rows * h;
    out.channels = c;
    out.pixels.assign(std::size_t(out.width) * out.height * c, 0);
    for (int t = 0; t < n; ++t)
        for (int y = 0; y < h; ++y)
            std::copy_n(frames[std::size_t(t)].pixels.begin() + std::ptrdiff_t(y) * w * c, std::size_t(w) * c,
                        out.pixels.begin() + (std::ptrdiff_t((t / cols) * h + y) * out.width + (t % cols) * w) * c);
    return out;
}

// Up to `count` frames evenly spread over the sequence.
Frames spread(const Frames& frames, std::size_t count) {
    if (frames.size() <= count) return frames;
    Frames out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(frames[i * frames.size() / count]);
    return out;
}

}  // namespace

Frames split_frames(const uint8_t* pixels, uint32_t width, uint32_t height, uint32_t channels, uint32_t frames) {
    Frames out;
    const std::size_t bytes = std::size_t(width) * height * channels;
    for (uint32_t t = 0; t < frames; ++t) {
        vqtex_metrics::Image img;
        img.width = int(width);
        img.height = int(height);
        img.channels = int(channels);
        img.pixels.assign(pixels + bytes * t, pixels + bytes * (t + 1));
        out.push_back(std::move(img));
    }
    return out;
}

Motion motion(const Frames& frames) {
    Motion m;
    if (frames.size() < 2) return m;
    std::vector<double> steps;
    for (std::size_t t = 0; t + 1 < frames.size(); ++t) steps.push_back(mean_abs_difference(frames[t], frames[t + 1]));
    double total = 0;
    for (double d : steps) total += d;
    m.change = total / double(steps.size());
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    m.loop = median > 0 ? mean_abs_difference(frames.back(), frames.front()) / median : 0.0;
    return m;
}

double swd_floor(const Frames& example) {
    if (example.empty()) throw std::invalid_argument("anim_stats: an empty example");
    const std::size_t n = example.size();
    double floor = 0;
    for (std::size_t t = 0; t < n; ++t)
        floor += vqtex_metrics::sliced_wasserstein(example[t], example[(t + n / 2) % n]).mean;
    return floor / double(n);
}

AnimStats anim_stats(const Frames& example, const Frames& output, const AnimStatsOptions& options) {
    if (example.empty() || output.empty()) throw std::invalid_argument("anim_stats: an empty sequence");
    AnimStats s;
    s.frames = uint32_t(output.size());
    // Every output frame against all the example's frames: the engine
    // starts anywhere in the example's time, and an example that pans shows
    // in one frame what another does not.
    const vqtex_metrics::Image all = mosaic(example);
    const vqtex_metrics::Image some = options.seam_visibility ? mosaic(spread(example, kSeamFrames)) : all;
    for (std::size_t f = 0; f < output.size(); ++f) {
        s.swd += vqtex_metrics::sliced_wasserstein(output[f], all).mean;
        if (options.coherence) s.coherence += vqtex_metrics::coherence(output[f], all, 7, 256, options.seed);
        if (options.seam_visibility)
            s.seam_visibility += vqtex_metrics::seam_visibility(output[f], some, false, options.threads);
    }
    const double n = double(output.size());
    s.swd /= n;
    s.coherence /= n;
    s.seam_visibility /= n;
    s.output = motion(output);
    s.example = motion(example);
    s.change_ratio = s.example.change > 0 ? s.output.change / s.example.change : 0.0;
    return s;
}

}  // namespace vqtex_tools
