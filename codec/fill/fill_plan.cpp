// fill_plan.cpp - choosing the pyramid depth, shapes and windows of a hole
// filling (paper section 5.1; see fill_plan.hpp).
#include "fill/fill_plan.hpp"

#include <algorithm>
#include <string>

#include "common/error.hpp"
#include "engine/pyramid.hpp"

namespace vqtex::constrained {

namespace {

// Why a pyramid of some depth cannot be used, for the error message.
struct Shortfall {
    std::string what;
};

bool try_plan(int levels, const FillOptions& o, int width, int height, const std::vector<uint8_t>& known0,
              const Image* example, Plan& plan, Shortfall& why) {
    plan = Plan{};
    plan.levels = levels;
    plan.target_known = o.method == FillMethod::TwoPass && o.context_threshold > 0 ? context_known_pyramid(width, height, known0, levels, o.context_threshold)
                                                : known_pyramid(width, height, known0, levels);
    plan.example_known = example ? known_pyramid(example->width, example->height,
                                                 std::vector<uint8_t>(example->pixel_count(), 1), levels)
                                 : known_pyramid(width, height, known0, levels);
    const std::vector<KnownLevel>& ek = plan.example_known;
    const std::vector<Shape> shapes = default_shapes(levels);
    plan.level.resize(std::size_t(levels));
    for (int l = levels - 1; l >= 0; --l) {
        LevelPlan& lp = plan.level[std::size_t(l)];
        lp.shape = shapes[std::size_t(l)];
        lp.shape.levels = std::min(lp.shape.levels, levels - l);
        lp.shape.causal = o.method == FillMethod::Causal;
        lp.main = lp.shape.causal ? causal_window(lp.shape) : symmetric_window(lp.shape);
        const std::string where = " at pyramid level " + std::to_string(l) + " of " + std::to_string(levels);
        if (plan.target_known[std::size_t(l)].known_count() == 0) {
            why.what = "no pixel of the image stays known" + where;
            return false;
        }
        lp.examples = count_examples(ek, l, lp.main, false);
        if (lp.examples < kMinFillExamples) {
            why.what = "only " + std::to_string(lp.examples) + " example neighbourhoods " +
                       shape_to_string(lp.shape) + " lie wholly in known pixels" + where +
                       " (at least " + std::to_string(kMinFillExamples) + " are needed)";
            return false;
        }
        if (o.method == FillMethod::TwoPass && l + 1 < levels) {
            lp.block = block_window(lp.shape);
            lp.blocks = count_examples(ek, l, lp.block, true);
            if (lp.blocks < kMinFillExamples) {
                why.what = "only " + std::to_string(lp.blocks) + " coarse example windows lie wholly in known pixels" +
                           where + " (at least " + std::to_string(kMinFillExamples) + " are needed)";
                return false;
            }
        }
    }
    return true;
}

}  // namespace

Plan make_plan(const FillOptions& o, const Image& image, const std::vector<uint8_t>& known0,
               const Image* example) {
    const Image& ex = example ? *example : image;
    if (o.levels < 0 || o.levels > kMaxLevels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "levels must be 0 (automatic) to " + std::to_string(kMaxLevels));
    const int deepest = o.levels ? o.levels
                                 : automatic_levels(std::min(ex.width, image.width), std::min(ex.height, image.height));
    Plan plan;
    Shortfall why;
    for (int levels = deepest; levels >= (o.levels ? o.levels : 1); --levels)
        if (try_plan(levels, o, image.width, image.height, known0, example, plan, why)) return plan;
    fail(VQTEX_ERROR_IMAGE_TOO_SMALL,
         "the mask leaves too little example: " + why.what +
             "; make the masked region smaller" + (o.levels ? std::string(", use fewer --levels") : std::string()) +
             (example ? std::string(" or give a larger example image") : std::string(" or give a separate example image (--example)")));
}

}  // namespace vqtex::constrained
