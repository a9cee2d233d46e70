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

#include "analysis/example_period.hpp"
#include "analysis/example_wrap.hpp"
#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/quilt.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "format/atlas_file.hpp"
#include "writer/atlas_writer.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

vqtex_metrics::Image as_metrics_image(const Image& img) { return {img.width, img.height, img.channels, img.pixels}; }

uint64_t atlas_budget_of_quality(int quality, uint64_t pixels) {
    const double per_128x128 = 1000.0 * std::pow(2.0, double(quality) / 25.0);
    return std::max<uint64_t>(512, uint64_t(std::llround(per_128x128 * double(pixels) / (128.0 * 128.0))));
}

namespace {

// The top-left crop of `scale`/16 of each side, within the atlas limits.
Image top_left_crop(const Image& example, int scale) {
    const int w = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.width * scale / 16));
    const int h = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.height * scale / 16));
    return example.crop(0, 0, std::min(w, example.width), std::min(h, example.height));
}

// The files of one atlas at the levels tried so far. The header names the
// example's size (what a decode makes by default), whatever part of it the
// atlas holds.
class LevelSearch {
public:
    LevelSearch(const Image& example, Image atlas, AtlasWrap wrap, const AtlasChoiceOptions& o, uint32_t* attempts,
                int speed = AtlasEncodeOptions{}.speed, std::array<int, 2> origin = {0, 0})
        : example_(example), atlas_(std::move(atlas)), wrap_(wrap), options_(o), attempts_(attempts),
          speed_(speed), origin_(origin) {
        const int deepest = coherent_levels(atlas_.width, atlas_.height);
        levels_ = o.levels ? std::min(o.levels, deepest) : deepest;
    }

    const std::vector<uint8_t>& file_at(int cq) {
        auto it = files_.find(cq);
        if (it != files_.end()) return it->second;
        AtlasEncodeOptions ao;
        ao.cq_level = cq;
        ao.speed = speed_;
        const std::vector<uint8_t> bits = encode_atlas(atlas_, ao);
        ++*attempts_;
        FileHeader h;
        h.exemplar_width = uint32_t(example_.width);
        h.exemplar_height = uint32_t(example_.height);
        h.channels = uint8_t(example_.channels);
        h.levels = uint8_t(levels_);
        h.seed = options_.seed;
        h.atlas_x = uint32_t(origin_[0]);
        h.atlas_y = uint32_t(origin_[1]);
        // The engine's defaults, as vqtex_synthesize runs it (synth_api.cpp).
        AtlasSynthesisParams sp;
        sp.example_tileable = wrap_.wraps;
        sp.period_bar = wrap_.period_bar;
        return files_.emplace(cq, encode_atlas_file(h, atlas_.width, atlas_.height, bits, sp)).first->second;
    }

    // The finest level whose file fits the budget, or -1.
    int finest_fitting() {
        return finest_fitting_level(options_.budget, [this](int cq) { return uint64_t(file_at(cq).size()); });
    }

    // The finest fitting level near `guess` (finest_fitting_near).
    int finest_fitting_near(int guess) {
        return vqtex::finest_fitting_near(options_.budget, guess, [this](int cq) { return uint64_t(file_at(cq).size()); });
    }

    AtlasChoice choice(int cq) {
        AtlasChoice c;
        c.file = file_at(cq);
        c.cq = cq;
        c.levels = levels_;
        c.atlas = atlas_;
        c.x = origin_[0];
        c.y = origin_[1];
        c.attempts = *attempts_;
        return c;
    }

private:
    const Image& example_;
    Image atlas_;
    AtlasWrap wrap_;
    AtlasChoiceOptions options_;
    uint32_t* attempts_;
    int speed_ = 4;
    std::array<int, 2> origin_{};  // where the atlas lies in the example
    int levels_ = 0;
    std::map<int, std::vector<uint8_t>> files_;
};

// The texture the decoder makes from a candidate file (seeds of its own).
vqtex_metrics::Image proxy_texture(const std::vector<uint8_t>& file, int width, int height, uint64_t seed,
                                   int threads) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = uint32_t(width);
    p.height = uint32_t(height);
    p.seed = seed;
    p.threads = uint32_t(threads);
    vqtex_image out{};
    vqtex_error err{};
    if (vqtex_decode(&p, file.data(), file.size(), &out, &err) != VQTEX_OK)
        fail(VQTEX_ERROR_INTERNAL, std::string("a candidate atlas did not decode: ") + err.detail);
    vqtex_metrics::Image texture{int(out.width), int(out.height), int(out.channels),
                                 std::vector<uint8_t>(out.pixels, out.pixels + std::size_t(out.width) * out.height * out.channels)};
    vqtex_image_free(&out);
    return texture;
}

// That texture scored against the example (seed 2).
ProxyScores proxy_scores(const vqtex_metrics::Image& reference, const std::vector<uint8_t>& file, int width,
                         int height, int max_windows = 262144, int threads = 1) {
    return proxy_scores_of(reference, proxy_texture(file, width, height, 2, threads), max_windows);
}

// The same atlas file laid out by quilting (format 21): its bitstream and
// fields, the period bar dropped.
std::vector<uint8_t> quilted_file(const std::vector<uint8_t>& file) {
    // The encoder made this file: any memory it needs was already spent.
    const AtlasFile f = decode_atlas_file(file.data(), file.size(), std::size_t(1) << 30);
    AtlasSynthesisParams sp = f.params;
    sp.period_bar = false;
    sp.quilt = quilt_block(f.atlas.width, f.atlas.height);
    sp.quilt_wavefront = true;
    sp.quilt_planar_cut = true;
    return encode_atlas_file(f.header, f.atlas.width, f.atlas.height,
                             std::vector<uint8_t>(file.begin() + long(f.bitstream_offset),
                                                  file.begin() + long(f.bitstream_offset + f.atlas_bytes)),
                             sp);
}

// Whether quilting beats the coherent engine on this example (kQuiltGain),
// on the means of kQuiltProxySeeds decodes of each.
bool quilting_wins(const Image& example, const std::vector<uint8_t>& coherent, const std::vector<uint8_t>& quilted,
                   int threads) {
    const vqtex_metrics::Image reference = as_metrics_image(example);
    const int w = std::min(512, 2 * example.width), h = std::min(512, 2 * example.height);
    struct Scores {
        double half = 0, coherence = 0, swd = 0;
    };
    const auto score = [&](const std::vector<uint8_t>& file) {
        Scores s;
        for (int k = 0; k < kQuiltProxySeeds; ++k) {
            const vqtex_metrics::Image t = proxy_texture(file, w, h, uint64_t(2 + k), threads);
            s.half += vqtex_metrics::coherence_half_resolution(t, reference, 7, 1024) / kQuiltProxySeeds;
            s.coherence += vqtex_metrics::coherence(t, reference, 7, 1024) / kQuiltProxySeeds;
            s.swd += vqtex_metrics::sliced_wasserstein(t, reference).mean / kQuiltProxySeeds;
        }
        return s;
    };
    const Scores e = score(coherent), q = score(quilted);
    return q.half <= (1 - kQuiltGain) * e.half && q.coherence <= (1 - kQuiltGain) * e.coherence &&
           q.swd <= (1 + kQuiltSwdSlack) * e.swd;
}

}  // namespace

ProxyScores proxy_scores_of(const vqtex_metrics::Image& reference, const vqtex_metrics::Image& texture,
                            int max_windows) {
    ProxyScores s;
    s.completeness = vqtex_metrics::completeness(reference, texture, 7, 256, vqtex_metrics::kDefaultSeed, max_windows);
    s.swd = vqtex_metrics::sliced_wasserstein(texture, reference).mean;
    s.coherence = vqtex_metrics::coherence(texture, reference, 7, 256, vqtex_metrics::kDefaultSeed, max_windows);
    return s;
}

std::vector<int> large_part_sides(uint64_t budget, int limit) {
    std::vector<int> sides;
    for (double per_128x128 : {4000.0, 2000.0, 1000.0}) {
        int s = int(std::lround(128.0 * std::sqrt(double(budget) / per_128x128) / 8.0)) * 8;
        s = std::clamp(s, 4 * kMinAtlasSide, limit);
        if (std::find(sides.begin(), sides.end(), s) == sides.end()) sides.push_back(s);
    }
    return sides;
}

void fail_nothing_fits(const std::string& what, uint64_t budget) {
    fail(VQTEX_ERROR_LIMIT_EXCEEDED, "no " + what + " fits in " + std::to_string(budget) +
                                         " bytes (the smallest needs more): raise --target-size or --quality");
}

int best_relative(const std::vector<std::vector<ProxyScores>>& scores) {
    std::vector<ProxyScores> least;
    for (const std::vector<ProxyScores>& c : scores) {
        if (least.size() < c.size()) least.resize(c.size(), ProxyScores{1e300, 1e300, 1e300});
        for (std::size_t m = 0; m < c.size(); ++m) {
            least[m].completeness = std::min(least[m].completeness, c[m].completeness);
            least[m].swd = std::min(least[m].swd, c[m].swd);
            least[m].coherence = std::min(least[m].coherence, c[m].coherence);
        }
    }
    int best = -1;
    double best_score = 1e300;
    for (std::size_t i = 0; i < scores.size(); ++i) {
        if (scores[i].empty()) continue;
        double score = 0;
        for (std::size_t m = 0; m < scores[i].size(); ++m)
            score += scores[i][m].completeness / std::max(least[m].completeness, 1e-9) +
                     scores[i][m].swd / std::max(least[m].swd, 1e-9) +
                     scores[i][m].coherence / std::max(least[m].coherence, 1e-9);
        if (score < best_score) {
            best_score = score;
            best = int(i);
        }
    }
    return best;
}

namespace {

// Budgets up to this many bytes per example pixel (about 2 KB for
// 128x128) also try crops: above it, no crop was ever chosen (docs/ATLAS.md).
constexpr double kCropBytesPerPixel = 0.13;

// An example up to kLargeExamplePixels (`source`: the example, or the tile
// it repeats): the whole of it, or at small budgets a crop of it.
AtlasChoice choose_whole_or_crop(const Image& example, const Image& source, AtlasWrap wrap,
                                 const AtlasChoiceOptions& options) {
    uint32_t attempts = 0;
    AtlasChoice whole;
    {
        LevelSearch search(example, source, wrap, options, &attempts);
        const int cq = search.finest_fitting();
        if (cq >= 0) whole = search.choice(cq);
    }
    if (!whole.file.empty()) {
        if (double(options.budget) > kCropBytesPerPixel * double(source.pixel_count()) ||
            std::min(source.width, source.height) < 4 * kMinAtlasSide)
            return whole;
        // A smaller part of the example coded more finely is sharper but
        // has less variety (docs/ATLAS.md "Which atlas"). The encoder keeps
        // the crops whose texture finds the example's windows as well as the
        // whole example's does (completeness), and among them takes the one
        // whose texture looks most like the example (SWD and coherence, each
        // relative to the whole example's).
        const int side = std::min(source.width, source.height);
        std::vector<std::array<int, 3>> regions;  // x, y, side
        for (int s : {side * 3 / 4, side / 2}) {
            regions.push_back({0, 0, s});
            regions.push_back({(source.width - s) / 2, (source.height - s) / 2, s});
        }
        std::vector<AtlasChoice> crops(regions.size());
        std::vector<ProxyScores> scores(regions.size() + 1);
        std::vector<uint32_t> crop_attempts(regions.size(), 0);
        const int w2 = 2 * source.width, h2 = 2 * source.height;
        const vqtex_metrics::Image reference = as_metrics_image(source);
        parallel_for(options.threads, regions.size() + 1, 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                if (i == regions.size()) {
                    scores[i] = proxy_scores(reference, whole.file, w2, h2);
                    continue;
                }
                const auto [x, y, s] = regions[i];
                LevelSearch search(example, source.crop(x, y, s, s), AtlasWrap{}, options, &crop_attempts[i],
                                   AtlasEncodeOptions{}.speed, {x, y});
                const int cq = search.finest_fitting();
                if (cq < 0) continue;
                crops[i] = search.choice(cq);
                scores[i] = proxy_scores(reference, crops[i].file, w2, h2);
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
        Image atlas = top_left_crop(source, scale);
        const bool smallest = (atlas.width == kMinAtlasSide && atlas.height == kMinAtlasSide) || scale == 1;
        LevelSearch search(example, std::move(atlas), AtlasWrap{}, options, &attempts);
        const int cq = search.finest_fitting();
        if (cq >= 0) return search.choice(cq);
        if (smallest) break;
    }
    fail_nothing_fits("atlas", options.budget);
}

// Per-channel mean and spread of `img` over a w x h window at (x, y), on
// every second row and column.
std::array<double, 8> colour_moments(const Image& img, int x0, int y0, int w, int h) {
    std::array<double, 8> sum{}, sq{};
    double n = 0;
    for (int y = y0; y < y0 + h; y += 2)
        for (int x = x0; x < x0 + w; x += 2) {
            const uint8_t* p = img.at(x, y);
            for (int c = 0; c < img.channels; ++c) {
                sum[c] += p[c];
                sq[c] += double(p[c]) * p[c];
            }
            n += 1;
        }
    std::array<double, 8> m{};
    for (int c = 0; c < img.channels; ++c) {
        m[c] = sum[c] / n;
        m[4 + c] = std::sqrt(std::max(0.0, sq[c] / n - m[c] * m[c]));
    }
    return m;
}

// An example above kLargeExamplePixels: square parts of `source` at
// sides the budget sets, coded at their finest fitting level, compete on
// the proxy's scores, each relative to the best candidate's.
AtlasChoice choose_part(const Image& example, const Image& source, bool source_wraps,
                        const AtlasChoiceOptions& options) {
    const std::vector<int> sides =
        large_part_sides(options.budget, std::min({source.width, source.height, kMaxAtlasSide}));
    std::vector<AtlasChoice> candidates(sides.size());
    std::vector<ProxyScores> scores(sides.size());
    std::vector<uint32_t> attempts(sides.size(), 0);
    parallel_for(options.threads, sides.size(), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const int s = sides[i];
            // The whole source when the side reaches it (a square tile),
            // which then keeps its wrap.
            const bool whole = s == source.width && s == source.height;
            const std::array<int, 2> at = whole ? std::array<int, 2>{0, 0} : representative_place(source, s);
            const Image part = source.crop(at[0], at[1], s, s);
            const AtlasWrap wraps{whole && source_wraps, false};
            LevelSearch fast(example, part, wraps, options, &attempts[i], kSearchSpeed, at);
            const int guess = fast.finest_fitting();
            LevelSearch fine(example, part, wraps, options, &attempts[i], kFinalSpeed, at);
            const int cq = fine.finest_fitting_near(guess < 0 ? 63 : guess);
            if (cq < 0) continue;
            candidates[i] = fine.choice(cq);
        }
    });
    // Together on the threads or one at a time (kProxiesTogetherPixels).
    const vqtex_metrics::Image reference = as_metrics_image(source);
    const bool together = source.pixel_count() <= kProxiesTogetherPixels;
    parallel_for(together ? options.threads : 1, sides.size(), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (candidates[i].file.empty()) continue;
            const int side = std::min(kLargeProxySide, 2 * sides[i]);
            scores[i] = proxy_scores(reference, candidates[i].file, side, side, kLargeProxyWindows,
                                     together ? 1 : options.threads);
        }
    });
    uint32_t total_attempts = 0;
    std::vector<std::vector<ProxyScores>> relative(sides.size());
    for (std::size_t i = 0; i < sides.size(); ++i) {
        total_attempts += attempts[i];
        if (!candidates[i].file.empty()) relative[i] = {scores[i]};
    }
    const int best = best_relative(relative);
    if (best < 0)
        fail_nothing_fits("atlas", options.budget);
    AtlasChoice chosen = std::move(candidates[std::size_t(best)]);
    chosen.attempts = total_attempts;
    return chosen;
}

}  // namespace

std::array<int, 2> representative_place(const Image& source, int s) {
    const std::array<double, 8> whole = colour_moments(source, 0, 0, source.width, source.height);
    std::array<int, 2> best{(source.width - s) / 2, (source.height - s) / 2};
    double best_d = 1e300;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            const int x = (source.width - s) * i / 2, y = (source.height - s) * j / 2;
            const std::array<double, 8> m = colour_moments(source, x, y, s, s);
            double d = 0;
            for (std::size_t k = 0; k < m.size(); ++k) d += (m[k] - whole[k]) * (m[k] - whole[k]);
            // Ties go to the centre, then in reading order.
            const bool centre = i == 1 && j == 1;
            if (d < best_d || (d == best_d && centre)) {
                best_d = d;
                best = {x, y};
            }
        }
    return best;
}

AtlasChoice choose_atlas(const Image& example, const AtlasChoiceOptions& options) {
    if (example.width < kMinAtlasSide || example.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an atlas needs an example of at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) + " pixels");
    // A large example that repeats holds nothing but its tile, which wraps
    // when it repeats both ways. (A small one is coded whole: its budget
    // follows its area, and a tile one row of features tall, say, gives the
    // engine too little to place.)
    const ExamplePeriod period = options.compaction && example.pixel_count() > kBudgetedPixels
                                     ? find_example_period(example)
                                     : ExamplePeriod{};
    const Image source = period.repeats() ? example.crop(0, 0, period.width, period.height) : example;
    const ExampleTiling tiling = example_tiling(example);
    // An example that repeats its tile is the tile tiled: its atlas wraps
    // freely. One that tiles without repeating wraps with the period bar,
    // so that copies run across its edges but the output does not repeat it
    // on a grid (docs/ATLAS.md "Examples that tile").
    const bool wraps = period.repeats() ? period.wraps()
                                        : options.example_tileable || (options.detect_tileable && tiling.wraps());
    const AtlasWrap wrap{wraps, wraps && !period.repeats() && tiling.period_bar()};
    AtlasChoiceOptions o = options;
    if (o.budget == 0)
        o.budget = atlas_budget_of_quality(o.quality, std::min<uint64_t>(source.pixel_count(), kBudgetedPixels));
    AtlasChoice c = options.compaction && source.pixel_count() > kLargeExamplePixels
                        ? choose_part(example, source, wraps, o)
                        : choose_whole_or_crop(example, source, wrap, o);
    c.tile = period.repeats() && c.atlas.width == source.width && c.atlas.height == source.height;
    c.wraps = wraps && c.atlas.width == source.width && c.atlas.height == source.height;
    c.period_bar = c.wraps && wrap.period_bar;
    c.example_tiles = tiling.tiles;
    if (c.wraps && !c.tile && options.layout != AtlasChoiceOptions::Layout::Coherent &&
        quilt_block(c.atlas.width, c.atlas.height) > 0) {
        std::vector<uint8_t> quilted = quilted_file(c.file);
        if (options.layout == AtlasChoiceOptions::Layout::Quilt || quilting_wins(source, c.file, quilted, options.threads)) {
            c.file = std::move(quilted);
            c.quilt = true;
            c.period_bar = false;
        }
    }
    return c;
}

}  // namespace vqtex
