// tree_model.cpp - the matchers the engine runs over a file's trees.
#include "format/tree_model.hpp"

#include "engine/synthesis.hpp"
#include "engine/temporal_synthesis.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex {
namespace {

std::shared_ptr<const Matcher> matcher_of(const std::shared_ptr<const Codebook>& book, uint32_t backtrack) {
    if (!book) return nullptr;
    return std::make_shared<TsvqMatcher>(book, backtrack);
}

// What a still's level and an animation's level both hold: the shape, the
// histogram and the causal and closing matchers of the level's trees.
template <typename Model, typename Stored>
void level_of(Model& tm, const Stored& lv, uint32_t backtrack) {
    tm.shape = lv.shape;
    tm.histogram = lv.histogram;
    tm.matcher = matcher_of(lv.causal, backtrack);
    tm.closing = matcher_of(lv.closing, backtrack);
    tm.closing_shape = lv.closing_shape;
}

}  // namespace

TextureModel texture_model_of(const CodecModel& model, uint32_t backtrack) {
    TextureModel t;
    t.channels = model.channels;
    for (const CodecModel::Level& lv : model.levels) level_of(t.levels.emplace_back(), lv, backtrack);
    return t;
}

VolumeModel volume_model_of(const VolumeCodecModel& model, uint32_t backtrack) {
    VolumeModel v;
    v.channels = model.channels;
    for (const VolumeCodecModel::Level& lv : model.levels) {
        VolumeLevelModel& tm = v.levels.emplace_back();
        level_of(tm, lv, backtrack);
        tm.seam = matcher_of(lv.seam, backtrack);
        tm.seam_shape = lv.seam_shape;
    }
    return v;
}

}  // namespace vqtex
