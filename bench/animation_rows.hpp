// The rows of vqtex-bench's animation protocol (animation_protocol.hpp) and
// their CSV, a schema of its own: one row per animation and output (the
// ceiling, vqtex and av1+synth at each rate point), with anim_stats.hpp's
// measures against the example. The protocol runs alone, so its CSV never
// mixes with the codec protocols' columns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "anim_stats.hpp"

namespace vqtex_tools {

struct AnimRow {
    std::string animation;
    std::string codec;          // ceiling, vqtex or av1+synth
    uint64_t target = 0;        // the rate point: a byte target, 0 for the default quality
    std::string setting;        // "default", "--target-size N", "cq N"
    std::string status = "ok";  // ok, limit-exceeded, no-fit, failed
    std::size_t bytes = 0;
    int width = 0, height = 0, frames = 0;
    AnimStats stats{};
    double swd_floor = 0;  // the example's (anim_stats.hpp)
    double encode_s = 0, decode_s = 0;
};

// The CSV (header at construction, when `f` is not null) and every row,
// kept for the summary. A row that is not ok has its measures at 0.
class AnimWriter {
public:
    explicit AnimWriter(FILE* f);
    void add(const AnimRow& r);
    std::vector<AnimRow> rows;

private:
    FILE* f_;
};

}  // namespace vqtex_tools
