// fill_plan.hpp - the plan of a hole filling (paper section 5.1): the
// pyramid depth, and per level the shapes and windows of its passes and how
// many example neighbourhoods serve them; the deepest pyramid whose every
// level has enough examples is chosen.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "fill/constrained.hpp"
#include "fill/fill_window.hpp"
#include "fill/known_pyramid.hpp"

namespace vqtex::constrained {

struct LevelPlan {
    Shape shape;              // pass-2 (symmetric) or causal shape
    Window main;              // pass-2 or causal window
    Window block;             // pass-1 window (two-pass, not the coarsest level)
    std::size_t examples = 0, blocks = 0;
};

struct Plan {
    int levels = 0;
    std::vector<LevelPlan> level;  // [0] = finest
    std::vector<KnownLevel> target_known, example_known;
};

// The plan for filling `known0`'s unknown pixels of `image` from `example`
// (or the image itself); fails with a message saying what to change when no
// depth works.
Plan make_plan(const FillOptions& o, const Image& image, const std::vector<uint8_t>& known0, const Image* example);

}  // namespace vqtex::constrained
