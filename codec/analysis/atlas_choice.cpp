// atlas_choice.cpp - the atlas of an atlas file and its AV1 level for a
// byte budget (docs/ATLAS.md "Which atlas" has the measurements
// behind the rules here).
#include "analysis/atlas_choice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "format/atlas_file.hpp"
#include "writer/atlas_writer.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

uint64_t atlas_budget_of_quality(int quality, uint64_t pixels) {
    const double per_128x128 = 1000.0 * std::pow(2.0, double(quality) / 25.0);
    return std::max<uint64_t>(512, uint64_t(std::llround(per_128x128 * double(pixels) / (128.0 * 128.0))));
}

namespace {

// The `w` x `h` pixels of the example at (x, y). A crop keeps the features
// at their scale, which downscaling would not.
Image crop(const Image& example, int x, int y, int w, int h) {
    if (x == 0 && y == 0 && w == example.width && h == example.height) return example;
    Image out(w, h, example.channels);
    for (int row = 0; row < h; ++row)
        std::memcpy(out.at(0, row), example.at(x, y + row), std::size_t(w) * std::size_t(example.channels));
    return out;
}

// The top-left crop of `scale`/16 of each side, within the atlas limits.
Image top_left_crop(const Image& example, int scale) {
    const int w = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.width * scale / 16));
    const int h = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.height * scale / 16));
    return crop(example, 0, 0, std::min(w, example.width), std::min(h, example.height));
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

    // The finest level whose file fits the budget, or -1.
    int finest_fitting() {
        return finest_fitting_level(options_.budget, [this](int cq) { return uint64_t(file_at(cq).size()); });
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

vqtex_metrics::Image as_metrics_image(const Image& img) { return {img.width, img.height, img.channels, img.pixels}; }

// What the encoder can measure of a file: the texture the decoder makes
// from it (2x2 the example, a seed of its own), against the example.
struct ProxyScores {
    double completeness = 0, swd = 0, coherence = 0;
};

ProxyScores proxy_scores(const Image& example, const std::vector<uint8_t>& file) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = uint32_t(2 * example.width);
    p.height = uint32_t(2 * example.height);
    p.seed = 2;
    p.threads = 1;  // the candidates run on the threads
    vqtex_image out{};
    vqtex_error err{};
    if (vqtex_decode(&p, file.data(), file.size(), &out, &err) != VQTEX_OK)
        fail(VQTEX_ERROR_INTERNAL, std::string("a candidate atlas did not decode: ") + err.detail);
    vqtex_metrics::Image texture{int(out.width), int(out.height), int(out.channels),
                                 std::vector<uint8_t>(out.pixels, out.pixels + std::size_t(out.width) * out.height * out.channels)};
    vqtex_image_free(&out);
    const vqtex_metrics::Image reference = as_metrics_image(example);
    ProxyScores s;
    s.completeness = vqtex_metrics::completeness(reference, texture);
    s.swd = vqtex_metrics::sliced_wasserstein(texture, reference).mean;
    s.coherence = vqtex_metrics::coherence(texture, reference);
    return s;
}

// Budgets up to this many bytes per example pixel (about 2 KB for
// 128x128) also try crops: above it, no crop was ever chosen (docs/ATLAS.md).
constexpr double kCropBytesPerPixel = 0.13;

}  // namespace

AtlasChoice choose_atlas(const Image& example, const AtlasChoiceOptions& options) {
    if (example.width < kMinAtlasSide || example.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an atlas needs an example of at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) + " pixels");
    uint32_t attempts = 0;
    AtlasChoice whole;
    {
        LevelSearch search(example, example, options, &attempts);
        const int cq = search.finest_fitting();
        if (cq >= 0) whole = search.choice(cq);
    }
    if (!whole.file.empty()) {
        if (double(options.budget) > kCropBytesPerPixel * double(example.pixel_count()) ||
            std::min(example.width, example.height) < 4 * kMinAtlasSide)
            return whole;
        // A smaller part of the example coded more finely is sharper but
        // has less variety (docs/ATLAS.md "Which atlas"). The encoder keeps
        // the crops whose texture finds the example's windows as well as the
        // whole example's does (completeness), and among them takes the one
        // whose texture looks most like the example (SWD and coherence, each
        // relative to the whole example's).
        const int side = std::min(example.width, example.height);
        std::vector<std::array<int, 3>> regions;  // x, y, side
        for (int s : {side * 3 / 4, side / 2}) {
            regions.push_back({0, 0, s});
            regions.push_back({(example.width - s) / 2, (example.height - s) / 2, s});
        }
        std::vector<AtlasChoice> crops(regions.size());
        std::vector<ProxyScores> scores(regions.size() + 1);
        std::vector<uint32_t> crop_attempts(regions.size(), 0);
        parallel_for(options.threads, regions.size() + 1, 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                if (i == regions.size()) {
                    scores[i] = proxy_scores(example, whole.file);
                    continue;
                }
                const auto [x, y, s] = regions[i];
                LevelSearch search(example, crop(example, x, y, s, s), options, &crop_attempts[i]);
                const int cq = search.finest_fitting();
                if (cq < 0) continue;
                crops[i] = search.choice(cq);
                scores[i] = proxy_scores(example, crops[i].file);
            }
        });
        const ProxyScores& w = scores.back();
        AtlasChoice* best = &whole;
        double best_score = 2.0;  // the whole example's: 1 + 1
        for (std::size_t i = 0; i < regions.size(); ++i) {
            attempts += crop_attempts[i];
            if (crops[i].file.empty() || scores[i].completeness > w.completeness) continue;
            const double score = scores[i].swd / std::max(w.swd, 1e-9) + scores[i].coherence / std::max(w.coherence, 1e-9);
            if (score < best_score) {
                best_score = score;
                best = &crops[i];
            }
        }
        AtlasChoice chosen = std::move(*best);
        chosen.attempts = attempts;
        return chosen;
    }
    for (int scale = 12; scale >= 1; scale = scale * 3 / 4) {
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
