// atlas_choice.cpp - the atlas of a format v3 file and its AV1 level for a
// byte budget (issue 17; docs/ATLAS.md "Which atlas" has the measurements
// behind the rules here).
#include "analysis/atlas_choice.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_encoder.hpp"
#include "format/atlas_file.hpp"

namespace vqtex {

uint64_t atlas_budget_of_quality(int quality, uint64_t pixels) {
    const double per_128x128 = 1000.0 * std::pow(2.0, double(quality) / 25.0);
    return std::max<uint64_t>(512, uint64_t(std::llround(per_128x128 * double(pixels) / (128.0 * 128.0))));
}

namespace {

// The top-left crop of `scale`/16 of each side: a crop keeps the features
// at their scale, which downscaling would not.
Image top_left_crop(const Image& example, int scale) {
    const int w = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.width * scale / 16));
    const int h = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.height * scale / 16));
    if (w == example.width && h == example.height) return example;
    Image crop(std::min(w, example.width), std::min(h, example.height), example.channels);
    for (int y = 0; y < crop.height; ++y)
        std::memcpy(crop.at(0, y), example.at(0, y), std::size_t(crop.width) * std::size_t(crop.channels));
    return crop;
}

// The files of one atlas at the levels tried so far.
class LevelSearch {
public:
    LevelSearch(const Image& example, Image atlas, const AtlasChoiceOptions& o, uint32_t* attempts)
        : example_(example), atlas_(std::move(atlas)), options_(o), attempts_(attempts) {
        const int deepest = coherent_levels(atlas_.width, atlas_.height);
        levels_ = o.levels ? std::min(o.levels, deepest) : deepest;
    }

    const std::vector<uint8_t>& file_at(int cq) {
        auto it = files_.find(cq);
        if (it != files_.end()) return it->second;
        AtlasEncodeOptions ao;
        ao.cq_level = cq;
        const std::vector<uint8_t> bits = encode_atlas(atlas_, ao);
        ++*attempts_;
        FileHeader h;
        h.exemplar_width = uint32_t(example_.width);
        h.exemplar_height = uint32_t(example_.height);
        h.channels = uint8_t(example_.channels);
        h.levels = uint8_t(levels_);
        h.seed = options_.seed;
        // The engine's defaults, as vqtex_synthesize runs it (synth_api.cpp).
        AtlasSynthesisParams sp;
        sp.example_tileable = options_.example_tileable;
        return files_.emplace(cq, encode_atlas_file(h, atlas_.width, atlas_.height, bits, sp)).first->second;
    }

    // The finest level whose file fits the budget, or -1. Size falls as the
    // level rises, so the search bisects.
    int finest_fitting() {
        if (file_at(63).size() > options_.budget) return -1;
        int lo = 0, hi = 62, best = 63;  // the answer lies in [lo, hi + 1]
        while (lo <= hi) {
            const int mid = (lo + hi) / 2;
            if (file_at(mid).size() <= options_.budget) {
                best = mid;
                hi = mid - 1;
            } else {
                lo = mid + 1;
            }
        }
        return best;
    }

    AtlasChoice choice(int cq) {
        AtlasChoice c;
        c.file = file_at(cq);
        c.cq = cq;
        c.levels = levels_;
        c.atlas = atlas_;
        c.attempts = *attempts_;
        return c;
    }

private:
    const Image& example_;
    Image atlas_;
    AtlasChoiceOptions options_;
    uint32_t* attempts_;
    int levels_ = 0;
    std::map<int, std::vector<uint8_t>> files_;
};

}  // namespace

AtlasChoice choose_atlas(const Image& example, const AtlasChoiceOptions& options) {
    if (example.width < kMinAtlasSide || example.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an atlas needs an example of at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) + " pixels");
    uint32_t attempts = 0;
    for (int scale = 16; scale >= 1; scale = scale * 3 / 4) {
        Image atlas = top_left_crop(example, scale);
        const bool smallest = (atlas.width == kMinAtlasSide && atlas.height == kMinAtlasSide) || scale == 1;
        LevelSearch search(example, std::move(atlas), options, &attempts);
        const int cq = search.finest_fitting();
        if (cq >= 0) return search.choice(cq);
        if (smallest) break;
    }
    fail(VQTEX_ERROR_LIMIT_EXCEEDED, "no atlas fits in " + std::to_string(options.budget) +
                                         " bytes (the smallest needs more): raise --target-size or --quality");
}

}  // namespace vqtex
