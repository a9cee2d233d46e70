// anim-metrics - how an animated output (paper section 5.2) compares with its
// example: does every frame look like the example's frames, and does it move
// as much as the example does? Reads two frame sequences (example, output)
// and prints, on one JSON line:
//  - swd: the mean over output frames of the sliced Wasserstein distance
//    (metrics/, 4 levels of 7x7 patches) between the frame and all the
//    example's frames side by side, and swd_floor, each example frame
//    against the one half a loop later (what two frames of the same texture
//    score);
//  - change: the mean absolute difference between consecutive frames (grey
//    levels per sample, over all channels), for the output and the example,
//    and their ratio: near 1 keeps the motion, 0 is frozen, far above 1
//    flickers;
//  - loop: the change from the last frame back to the first, divided by the
//    median consecutive change (near 1 or below: the output loops).
// The measures are anim_stats.hpp's (shared with vqtex-bench's animation
// protocol). Not installed; bench/anim_report.sh runs it on the corpus
// animations.
#include <cstdio>
#include <stdexcept>

#include "anim_stats.hpp"
#include "sequence_io.hpp"

using namespace vqtex_tools;

namespace {

Frames frames_of(const LoadedSequence& s) {
    return split_frames(s.pixels.data(), s.width, s.height, s.channels, s.frames);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: anim-metrics EXAMPLE_SEQUENCE OUTPUT_SEQUENCE\n"
                             "  (a numbered pattern such as 'dir/frame_%%03d.png', or a folder of frames)\n");
        return 2;
    }
    try {
        const Frames ex = frames_of(load_sequence(argv[1]));
        const Frames out = frames_of(load_sequence(argv[2]));
        const AnimStats s = anim_stats(ex, out);
        std::printf("{\"example\":\"%s\",\"output\":\"%s\",\"frames\":%u,\"swd\":%.3f,\"swd_floor\":%.3f,"
                    "\"change\":%.3f,\"example_change\":%.3f,\"change_ratio\":%.3f,\"loop\":%.3f,"
                    "\"example_loop\":%.3f}\n",
                    argv[1], argv[2], s.frames, s.swd, swd_floor(ex), s.output.change, s.example.change,
                    s.change_ratio, s.output.loop, s.example.loop);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "anim-metrics: error: %s\n", e.what());
        return 1;
    }
}
