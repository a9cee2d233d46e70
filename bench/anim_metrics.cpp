// anim-metrics - how an animated output (paper section 5.2) compares with its
// example: does every frame look like the example's frames, and does it move
// as much as the example does? Reads two frame sequences (example, output)
// and prints, on one JSON line:
//  - swd: the mean over output frames f of the sliced Wasserstein distance
//    (metrics/, 4 levels of 7x7 patches) between frame f and example frame
//    f mod T, and swd_floor, the same between each example frame and the one
//    half a loop later (what two frames of the same texture score);
//  - change: the mean absolute difference between consecutive frames (grey
//    levels per sample, over all channels), for the output and the example,
//    and their ratio: near 1 keeps the motion, 0 is frozen, far above 1
//    flickers;
//  - loop: the change from the last frame back to the first, divided by the
//    median consecutive change (near 1 or below: the output loops).
// Not installed; bench/anim_report.sh runs it on the corpus animations.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "metrics.hpp"
#include "sequence_io.hpp"

using namespace vqtex_tools;

namespace {

vqtex_metrics::Image frame_of(const LoadedSequence& s, uint32_t t) {
    vqtex_metrics::Image img;
    img.width = int(s.width);
    img.height = int(s.height);
    img.channels = int(s.channels);
    const std::size_t bytes = std::size_t(s.width) * s.height * s.channels;
    img.pixels.assign(s.pixels.begin() + std::ptrdiff_t(bytes * t), s.pixels.begin() + std::ptrdiff_t(bytes * (t + 1)));
    return img;
}

double mean_abs_difference(const LoadedSequence& s, uint32_t a, uint32_t b) {
    const std::size_t bytes = std::size_t(s.width) * s.height * s.channels;
    const uint8_t* pa = s.pixels.data() + bytes * a;
    const uint8_t* pb = s.pixels.data() + bytes * b;
    uint64_t sum = 0;
    for (std::size_t i = 0; i < bytes; ++i) sum += uint64_t(std::abs(int(pa[i]) - int(pb[i])));
    return double(sum) / double(bytes);
}

struct Motion {
    double change = 0;  // mean consecutive change
    double loop = 0;    // last-to-first change over the median consecutive change
};

Motion motion(const LoadedSequence& s) {
    Motion m;
    if (s.frames < 2) return m;
    std::vector<double> steps;
    for (uint32_t t = 0; t + 1 < s.frames; ++t) steps.push_back(mean_abs_difference(s, t, t + 1));
    double total = 0;
    for (double d : steps) total += d;
    m.change = total / double(steps.size());
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    m.loop = median > 0 ? mean_abs_difference(s, s.frames - 1, 0) / median : 0.0;
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: anim-metrics EXAMPLE_SEQUENCE OUTPUT_SEQUENCE\n"
                             "  (a numbered pattern such as 'dir/frame_%%03d.png', or a folder of frames)\n");
        return 2;
    }
    try {
        const LoadedSequence ex = load_sequence(argv[1]);
        const LoadedSequence out = load_sequence(argv[2]);
        double swd = 0, floor = 0;
        for (uint32_t f = 0; f < out.frames; ++f)
            swd += vqtex_metrics::sliced_wasserstein(frame_of(out, f), frame_of(ex, f % ex.frames)).mean;
        swd /= double(out.frames);
        for (uint32_t t = 0; t < ex.frames; ++t)
            floor += vqtex_metrics::sliced_wasserstein(frame_of(ex, t), frame_of(ex, (t + ex.frames / 2) % ex.frames)).mean;
        floor /= double(ex.frames);
        const Motion me = motion(ex), mo = motion(out);
        std::printf("{\"example\":\"%s\",\"output\":\"%s\",\"frames\":%u,\"swd\":%.3f,\"swd_floor\":%.3f,"
                    "\"change\":%.3f,\"example_change\":%.3f,\"change_ratio\":%.3f,\"loop\":%.3f,"
                    "\"example_loop\":%.3f}\n",
                    argv[1], argv[2], out.frames, swd, floor, mo.change, me.change,
                    me.change > 0 ? mo.change / me.change : 0.0, mo.loop, me.loop);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "anim-metrics: error: %s\n", e.what());
        return 1;
    }
}
