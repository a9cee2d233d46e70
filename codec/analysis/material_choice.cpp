// material_choice.cpp - the guide and the atlas of a set of maps (see
// material_choice.hpp).
#include "analysis/material_choice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include "analysis/example_wrap.hpp"
#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "writer/atlas_writer.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {
namespace {

// Eigenvectors of a symmetric n x n matrix by cyclic Jacobi rotations, as
// columns of `vectors`, eigenvalues on the diagonal of `a` afterwards. The
// matrices here are at most 64 x 64 and this runs once per encode.
void jacobi_eigen(std::vector<double>& a, std::vector<double>& vectors, int n) {
    vectors.assign(std::size_t(n) * std::size_t(n), 0.0);
    for (int i = 0; i < n; ++i) vectors[std::size_t(i) * std::size_t(n) + std::size_t(i)] = 1.0;
    const auto at = [n](std::vector<double>& m, int r, int c) -> double& {
        return m[std::size_t(r) * std::size_t(n) + std::size_t(c)];
    };
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = 0;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) off += at(a, p, q) * at(a, p, q);
        if (off < 1e-18) break;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) {
                const double apq = at(a, p, q);
                if (std::abs(apq) < 1e-300) continue;
                const double theta = (at(a, q, q) - at(a, p, p)) / (2 * apq);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < n; ++k) {
                    const double akp = at(a, k, p), akq = at(a, k, q);
                    at(a, k, p) = c * akp - s * akq;
                    at(a, k, q) = s * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) {
                    const double apk = at(a, p, k), aqk = at(a, q, k);
                    at(a, p, k) = c * apk - s * aqk;
                    at(a, q, k) = s * apk + c * aqk;
                }
                for (int k = 0; k < n; ++k) {
                    const double vkp = at(vectors, k, p), vkq = at(vectors, k, q);
                    at(vectors, k, p) = c * vkp - s * vkq;
                    at(vectors, k, q) = s * vkp + c * vkq;
                }
            }
    }
}

}  // namespace

MaterialMap map_from_16_bits(std::string name, MapKind kind, int weight, const Image16& samples) {
    MaterialMap m;
    m.name = std::move(name);
    m.kind = kind;
    m.weight = weight;
    m.bits = kHighBitDepth;
    m.image16 = Image16(samples.width, samples.height, samples.channels);
    m.image = Image(samples.width, samples.height, samples.channels);
    const uint32_t top = (1u << kHighBitDepth) - 1;
    for (std::size_t i = 0; i < samples.pixels.size(); ++i) {
        const uint16_t v = uint16_t((uint32_t(samples.pixels[i]) * top + 32767) / 65535);
        m.image16.pixels[i] = v;
        m.image.pixels[i] = uint8_t(v >> (kHighBitDepth - 8));
    }
    return m;
}

// On a grid of at most 65536 pixels. Pooled about one mean, the channels'
// different means counted as contrast: a normal map's blue near 250
// against red and green near 127 made the corpus's normal maps 54-62
// levels (7-20 channel by channel) and lava's orange albedo 84 (25), so a
// normal map took the level of the set's most contrasty map and was coded
// coarser than its detail needs.
double map_contrast(const Image& image) {
    const std::size_t pixels = image.pixel_count(), step = std::max<std::size_t>(1, pixels / 65536);
    double variance = 0;
    for (int c = 0; c < image.channels; ++c) {
        double sum = 0, sum2 = 0, count = 0;
        for (std::size_t i = 0; i < pixels; i += step) {
            const double v = image.pixels[i * std::size_t(image.channels) + std::size_t(c)];
            sum += v, sum2 += v * v, count += 1;
        }
        const double mean = sum / count;
        variance += std::max(0.0, sum2 / count - mean * mean);
    }
    return std::sqrt(variance / image.channels);
}

namespace {

// The deviation below which a map is taken as flat: its noise is not
// stretched to the others' contrast.
constexpr double kFlatDeviation = 4.0;

}  // namespace

namespace {

// Solves the n x n system a x = b (a symmetric, positive semi-definite) by
// Gaussian elimination with partial pivoting; false when it is singular.
bool solve(std::vector<double> a, std::vector<double> b, int n, std::vector<double>& x) {
    const auto at = [n](std::vector<double>& m, int r, int c) -> double& {
        return m[std::size_t(r) * std::size_t(n) + std::size_t(c)];
    };
    for (int k = 0; k < n; ++k) {
        int pivot = k;
        for (int r = k + 1; r < n; ++r)
            if (std::abs(at(a, r, k)) > std::abs(at(a, pivot, k))) pivot = r;
        if (std::abs(at(a, pivot, k)) < 1e-9) return false;
        if (pivot != k) {
            for (int c = 0; c < n; ++c) std::swap(at(a, k, c), at(a, pivot, c));
            std::swap(b[std::size_t(k)], b[std::size_t(pivot)]);
        }
        for (int r = k + 1; r < n; ++r) {
            const double q = at(a, r, k) / at(a, k, k);
            for (int c = k; c < n; ++c) at(a, r, c) -= q * at(a, k, c);
            b[std::size_t(r)] -= q * b[std::size_t(k)];
        }
    }
    x.assign(std::size_t(n), 0.0);
    for (int k = n - 1; k >= 0; --k) {
        double t = b[std::size_t(k)];
        for (int c = k + 1; c < n; ++c) t -= at(a, k, c) * x[std::size_t(c)];
        x[std::size_t(k)] = t / at(a, k, k);
    }
    return true;
}

// The variance of `image`'s channels on the pixels of `grid`, summed over
// its channels; with `minus`, of image - minus.
double variance_on(const Image& image, const std::vector<std::size_t>& grid, const Image* minus = nullptr) {
    double sum = 0;
    for (int c = 0; c < image.channels; ++c) {
        double s = 0, s2 = 0;
        for (const std::size_t i : grid) {
            const std::size_t at = i * std::size_t(image.channels) + std::size_t(c);
            const double d = double(image.pixels[at]) - (minus ? double(minus->pixels[at]) : 0.0);
            s += d, s2 += d * d;
        }
        const double n = double(grid.size());
        sum += s2 / n - (s / n) * (s / n);
    }
    return sum;
}

// The residual the encoder codes for a predicted map (docs/FORMAT.md
// §4.17): what the decoder's add_prediction turns back into the map.
Image subtract_prediction(const Image& map, const Image& prediction) {
    Image out(map.width, map.height, map.channels);
    for (std::size_t i = 0; i < map.pixels.size(); ++i)
        out.pixels[i] = uint8_t(std::clamp(int(map.pixels[i]) - int(prediction.pixels[i]) + 128, 0, 255));
    return out;
}

// The deviation of a predicted map's residual below which it is not coded
// (a flat residual: the prediction alone).
constexpr double kRoundingDeviation = 1.0;

// The coding error of a source map, in levels, that a prediction is made
// robust to: about the default's on the corpus's albedos (the wood
// albedo's decoded atlas is 0.96 correlated with the example, 3 levels of
// its 11).
constexpr double kSourceNoise = 3.0;

}  // namespace

std::vector<MapPrediction> fit_map_predictions(const std::vector<MaterialMap>& maps) {
    std::vector<MapPrediction> predictions(maps.size());
    if (maps.size() < 2) return predictions;
    const std::size_t pixels = maps[0].image.pixel_count(), step = std::max<std::size_t>(1, pixels / 65536);
    std::vector<std::size_t> grid;
    for (std::size_t i = 0; i < pixels; i += step) grid.push_back(i);
    for (std::size_t m = 1; m < maps.size(); ++m) {
        const Image& map = maps[m].image;
        if (maps[m].bits != 8 || maps[m].kind == MapKind::Normal) continue;
        // A prediction must leave at most a quarter of the map's variance.
        double best = variance_on(map, grid) / 4;
        for (std::size_t j = 0; j < m; ++j) {
            if (maps[j].bits != 8) continue;
            const Image& src = maps[j].image;
            const int n = src.channels + 1;
            // Normal equations of [s_0 .. s_S-1, 1] -> each channel.
            std::vector<double> a(std::size_t(n) * std::size_t(n), 0.0);
            std::vector<std::vector<double>> b(std::size_t(map.channels), std::vector<double>(std::size_t(n), 0.0));
            std::vector<double> f(static_cast<std::size_t>(n), 0.0);
            for (const std::size_t i : grid) {
                for (int k = 0; k < src.channels; ++k)
                    f[std::size_t(k)] = src.pixels[i * std::size_t(src.channels) + std::size_t(k)];
                f[std::size_t(n - 1)] = 1;
                for (int r = 0; r < n; ++r)
                    for (int c = 0; c < n; ++c) a[std::size_t(r * n + c)] += f[std::size_t(r)] * f[std::size_t(c)];
                for (int c = 0; c < map.channels; ++c)
                    for (int r = 0; r < n; ++r)
                        b[std::size_t(c)][std::size_t(r)] +=
                            f[std::size_t(r)] * map.pixels[i * std::size_t(map.channels) + std::size_t(c)];
            }
            // The decoder predicts from the decoded source, whose coding
            // error the coefficients carry into the map: the fit is a ridge
            // that counts that error as noise of kSourceNoise levels on
            // each source channel (on a synthetic surface, a plain fit put
            // 3.3 on the albedo's blue and the decoded gloss lost 0.06 of
            // its correlation with the albedo).
            for (int k = 0; k + 1 < n; ++k)
                a[std::size_t(k * n + k)] += double(grid.size()) * kSourceNoise * kSourceNoise;
            MapPrediction p;
            p.source = int(j);
            bool solved = true;
            for (int c = 0; c < map.channels && solved; ++c) {
                std::vector<double> x;
                solved = solve(a, b[std::size_t(c)], n, x);
                if (!solved) break;
                // Q8 coefficients, then the offset that keeps the mean with
                // them as rounded (the sums of the constant term's row and
                // of b are the channels' sums over the grid).
                const double count = double(grid.size());
                double mean_in = 0;
                for (int k = 0; k < src.channels; ++k) {
                    const int32_t q = int32_t(std::clamp<long>(std::lround(x[std::size_t(k)] * 256.0),
                                                               -kMaxPredictionCoefficient, kMaxPredictionCoefficient));
                    p.coefficients.push_back(q);
                    mean_in += double(q) * a[std::size_t((n - 1) * n + k)] / count;
                }
                const double mean_out = b[std::size_t(c)][std::size_t(n - 1)] / count;
                p.offsets.push_back(int32_t(std::clamp<long>(std::lround(mean_out * 256.0 - mean_in - 128.0),
                                                             -kMaxPredictionOffset, kMaxPredictionOffset)));
            }
            if (!solved) continue;
            double gain = 0;  // the sum of the squared coefficients
            for (const int32_t q : p.coefficients) gain += (double(q) / 256.0) * (double(q) / 256.0);
            const Image prediction = predict_map(src, p, map.channels);
            const double left = variance_on(map, grid, &prediction) + kSourceNoise * kSourceNoise * gain;
            if (left < best) {
                best = left;
                predictions[m] = std::move(p);
            }
        }
    }
    return predictions;
}

GuideMatrix guide_matrix(const std::vector<MaterialMap>& maps) {
    GuideMatrix g;
    if (maps.size() < 2) return g;
    // Each map counts by its weight, not by its contrast: its channels are
    // scaled by weight / deviation (measured: with raw values, a contrasty
    // normal map led a dark lava albedo's synthesis, whose SWD was 15%
    // worse than the albedo's alone).
    std::vector<double> deviation;
    for (const MaterialMap& m : maps) deviation.push_back(map_contrast(m.image));
    const double most = std::max(*std::max_element(deviation.begin(), deviation.end()), kFlatDeviation);
    std::vector<double> weight;  // per channel
    for (std::size_t i = 0; i < maps.size(); ++i) {
        // A map of little contrast is raised at most fourfold against the
        // set's most contrasty one, so that its noise does not lead.
        const double scale = double(maps[i].weight) * 32.0 / std::max(deviation[i], most / 4);
        for (int c = 0; c < maps[i].image.channels; ++c) weight.push_back(scale);
    }
    const int n = int(weight.size());
    const Image& first = maps[0].image;
    // Up to 65536 pixels on a regular grid.
    const std::size_t pixels = first.pixel_count();
    const std::size_t step = std::max<std::size_t>(1, pixels / 65536);
    std::vector<double> mean(static_cast<std::size_t>(n), 0.0);
    std::vector<double> cov(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
    std::vector<double> v(static_cast<std::size_t>(n), 0.0);
    std::size_t count = 0;
    for (std::size_t i = 0; i < pixels; i += step, ++count) {
        std::size_t at = 0;
        for (const MaterialMap& m : maps)
            for (int c = 0; c < m.image.channels; ++c, ++at)
                v[at] = weight[at] * m.image.pixels[i * std::size_t(m.image.channels) + std::size_t(c)];
        for (int a = 0; a < n; ++a) {
            mean[std::size_t(a)] += v[std::size_t(a)];
            for (int b = a; b < n; ++b) cov[std::size_t(a) * std::size_t(n) + std::size_t(b)] += v[std::size_t(a)] * v[std::size_t(b)];
        }
    }
    for (double& m : mean) m /= double(count);
    for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b) {
            double& c = cov[std::size_t(a) * std::size_t(n) + std::size_t(b)];
            c = c / double(count) - mean[std::size_t(a)] * mean[std::size_t(b)];
            cov[std::size_t(b) * std::size_t(n) + std::size_t(a)] = c;
        }
    std::vector<double> vectors;
    jacobi_eigen(cov, vectors, n);
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) order[std::size_t(i)] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return cov[std::size_t(a) * std::size_t(n) + std::size_t(a)] > cov[std::size_t(b) * std::size_t(n) + std::size_t(b)];
    });
    g.channels = std::min(n, kMaxGuideChannels);
    // One scale for every component, so that their variances keep their
    // ratio: the strongest's ±3 standard deviations span 0..255 (a flat set
    // is not stretched past a standard deviation of 8 levels).
    const double strongest = std::max(cov[std::size_t(order[0]) * std::size_t(n) + std::size_t(order[0])], 0.0);
    const double scale = 255.0 / (6.0 * std::max(std::sqrt(strongest), 8.0));
    for (int k = 0; k < g.channels; ++k) {
        const int e = order[std::size_t(k)];
        double centre = 0;
        for (int c = 0; c < n; ++c) {
            const double axis = vectors[std::size_t(c) * std::size_t(n) + std::size_t(e)];
            const double coefficient = std::clamp(std::round(256.0 * scale * axis * weight[std::size_t(c)]),
                                                  double(-kMaxGuideCoefficient), double(kMaxGuideCoefficient));
            g.coefficients.push_back(int32_t(coefficient));
            centre += coefficient * mean[std::size_t(c)] / weight[std::size_t(c)];
        }
        g.offsets.push_back(int32_t(std::clamp(std::round(256.0 * 128.0 - centre), double(-kMaxGuideOffset),
                                               double(kMaxGuideOffset))));
    }
    return g;
}

namespace {

// The files of one part of a set's maps (each map's atlas at the same
// place) at the levels tried so far. The maps code independently (libaom
// on one thread each), so the bytes do not depend on the thread count.
class SetLevelSearch {
public:
    SetLevelSearch(const std::vector<MaterialMap>& maps, const GuideMatrix& guide, const std::vector<int>& offsets,
                   const std::vector<MapPrediction>& predictions, std::array<int, 4> part,
                   const AtlasChoiceOptions& options, int threads, uint32_t* attempts,
                   int speed = AtlasEncodeOptions{}.speed, bool period_bar = false)
        : maps_(maps), guide_(guide), offsets_(offsets), part_(part), options_(options), period_bar_(period_bar),
          threads_(threads), attempts_(attempts), speed_(speed) {
        const auto [x, y, w, h] = part;
        for (const MaterialMap& m : maps) {
            atlases_.push_back(m.image.crop(x, y, w, h));
            atlases16_.push_back(m.bits > 8 ? m.image16.crop(x, y, w, h) : Image16());
        }
        // A predicted map is coded as what its source's original samples do
        // not predict (the decoder predicts from the decoded source, so the
        // map follows the source's coding error). No version holds both
        // the period bar and predictions: a barred set codes its maps as
        // they are.
        predictions_.assign(maps.size(), MapPrediction{});
        if (!barred())
            for (std::size_t i = 0; i < maps.size(); ++i) predictions_[i] = predictions[i];
        // A residual is coded at its source's level: what it holds beyond
        // the prediction is finer than the source's own coding error, and
        // a finer level spends bytes on the prediction's rounding (on
        // bricks, a gloss's residual at the gloss's finer level took 6
        // times the bytes of the gloss coded as it is).
        for (std::size_t i = maps.size(); i-- > 0;) {
            const MapPrediction& p = predictions_[i];
            if (!p.predicted()) continue;
            offsets_[i] = offsets_[std::size_t(p.source)];
            atlases_[i] = subtract_prediction(
                atlases_[i], predict_map(atlases_[std::size_t(p.source)], p, atlases_[i].channels));
            // A residual of under a level is the prediction's rounding and
            // the map's own noise: coded, it is white noise that costs as
            // much as the map (on bricks, at a fine level, 2.1 KB for a
            // gloss the prediction already gave within a level); dropped,
            // the map's error stays under a level.
            if (map_contrast(atlases_[i]) < kRoundingDeviation)
                std::fill(atlases_[i].pixels.begin(), atlases_[i].pixels.end(), uint8_t(128));
        }
        const int deepest = coherent_levels(w, h);
        levels_ = options.levels ? std::min(options.levels, deepest) : deepest;
    }

    const std::vector<uint8_t>& file_at(int cq) {
        auto it = files_.find(cq);
        if (it != files_.end()) return it->second;
        std::vector<CodedMap> coded(maps_.size());
        parallel_for(threads_, maps_.size(), 1, [&](std::size_t i0, std::size_t i1) {
            for (std::size_t i = i0; i < i1; ++i) {
                const MaterialMap& m = maps_[i];
                AtlasEncodeOptions ao;
                ao.cq_level = std::clamp(cq + offsets_[i], 0, 63);
                ao.speed = speed_;
                coded[i] = {m.name, m.kind, atlases_[i].channels, m.bits,
                            m.bits > 8 ? encode_atlas_high(atlases16_[i], m.bits, ao) : encode_atlas(atlases_[i], ao),
                            predictions_[i]};
            }
        });
        ++*attempts_;
        FileHeader hd;
        hd.exemplar_width = uint32_t(maps_[0].image.width);
        hd.exemplar_height = uint32_t(maps_[0].image.height);
        hd.levels = uint8_t(levels_);
        hd.seed = options_.seed;
        hd.atlas_x = uint32_t(part_[0]);
        hd.atlas_y = uint32_t(part_[1]);
        AtlasSynthesisParams sp;
        sp.example_tileable = wraps();
        sp.period_bar = barred();
        return files_.emplace(cq, encode_material_file(hd, part_[2], part_[3], coded, guide_, sp)).first->second;
    }

    uint64_t size_at(int cq) { return file_at(cq).size(); }

    MaterialChoice choice(int cq) {
        MaterialChoice c;
        c.file = file_at(cq);
        c.cq = cq;
        c.levels = levels_;
        c.atlas_x = part_[0];
        c.atlas_y = part_[1];
        c.atlas_width = part_[2];
        c.atlas_height = part_[3];
        c.wraps = wraps();
        c.period_bar = barred();
        return c;
    }

private:
    // The atlas wraps when the example does and the atlas is all of it.
    bool wraps() const {
        return options_.example_tileable && part_[2] == maps_[0].image.width && part_[3] == maps_[0].image.height;
    }
    // A wrapping atlas is decoded with the period bar unless a map repeats
    // a tile (`period_bar` false).
    bool barred() const { return wraps() && period_bar_; }

    const std::vector<MaterialMap>& maps_;
    const GuideMatrix& guide_;
    std::vector<int> offsets_;  // per map, added to the set's level
    std::array<int, 4> part_;  // x, y, w, h
    AtlasChoiceOptions options_;
    bool period_bar_ = false;
    int threads_ = 1;
    uint32_t* attempts_;
    int speed_ = 4;
    int levels_ = 0;
    std::vector<Image> atlases_;  // a predicted map's: its residual
    std::vector<Image16> atlases16_;
    std::vector<MapPrediction> predictions_;
    std::map<int, std::vector<uint8_t>> files_;
};

// The set a candidate file decodes to (side x side, a seed of its own),
// each map scored against its example.
std::vector<ProxyScores> set_proxy_scores(const std::vector<MaterialMap>& maps,
                                          const std::vector<vqtex_metrics::Image>& references,
                                          const std::vector<uint8_t>& file, int side, int threads) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = p.height = uint32_t(side);
    p.seed = 2;
    p.threads = uint32_t(threads);
    std::vector<vqtex_map_image> decoded(VQTEX_MAX_MAPS);
    uint32_t count = 0;
    vqtex_error err{};
    if (vqtex_decode_maps(&p, file.data(), file.size(), decoded.data(), VQTEX_MAX_MAPS, &count, &err) != VQTEX_OK)
        fail(VQTEX_ERROR_INTERNAL, std::string("a candidate set did not decode: ") + err.detail);
    std::vector<vqtex_metrics::Image> textures;
    for (uint32_t i = 0; i < count; ++i) {
        vqtex_map_image& d = decoded[i];
        if (d.bits == 8) {
            const std::size_t n = std::size_t(d.image.width) * d.image.height * d.image.channels;
            textures.push_back({int(d.image.width), int(d.image.height), int(d.image.channels),
                                std::vector<uint8_t>(d.image.pixels, d.image.pixels + n)});
        } else {
            // The guide's view of a deep map: its top 8 bits.
            const std::size_t n = std::size_t(d.image16.width) * d.image16.height * d.image16.channels;
            std::vector<uint8_t> top(n);
            for (std::size_t k = 0; k < n; ++k) top[k] = uint8_t(d.image16.pixels[k] >> 8);
            textures.push_back({int(d.image16.width), int(d.image16.height), int(d.image16.channels), std::move(top)});
        }
        vqtex_image_free(&d.image);
        vqtex_image16_free(&d.image16);
    }
    if (textures.size() != maps.size()) fail(VQTEX_ERROR_INTERNAL, "a candidate set decoded to the wrong map count");
    std::vector<ProxyScores> scores;
    for (std::size_t i = 0; i < maps.size(); ++i)
        scores.push_back(proxy_scores_of(references[i], textures[i], kLargeProxyWindows));
    return scores;
}

// A set above kLargeExamplePixels: square parts at the sides each map's
// share of the budget pays for (the stills' large path, atlas_choice.hpp),
// every map's atlas at the same place, each part coded at its finest
// fitting level; they compete on the proxy's scores of every map, each
// relative to the best candidate's.
MaterialChoice choose_material_part(const std::vector<MaterialMap>& maps, const GuideMatrix& guide,
                                    const std::vector<int>& offsets, const std::vector<MapPrediction>& predictions,
                                    const AtlasChoiceOptions& options) {
    const Image& first = maps[0].image;
    const std::vector<int> sides = large_part_sides(options.budget / maps.size(),
                                                    std::min({first.width, first.height, kMaxAtlasSide}));
    std::vector<MaterialChoice> candidates(sides.size());
    std::vector<uint32_t> attempts(sides.size(), 0);
    parallel_for(options.threads, sides.size(), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const int s = sides[i];
            const bool whole = s == first.width && s == first.height;
            const std::array<int, 2> at = whole ? std::array<int, 2>{0, 0} : representative_place(first, s);
            const std::array<int, 4> part{at[0], at[1], s, s};
            SetLevelSearch fast(maps, guide, offsets, predictions, part, options, 1, &attempts[i], kSearchSpeed);
            const int guess = finest_fitting_level(options.budget, [&](int cq) { return fast.size_at(cq); });
            SetLevelSearch fine(maps, guide, offsets, predictions, part, options, 1, &attempts[i], kFinalSpeed);
            const int cq = finest_fitting_near(options.budget, guess, [&](int q) { return fine.size_at(q); });
            if (cq >= 0) candidates[i] = fine.choice(cq);
        }
    });
    std::vector<vqtex_metrics::Image> references;
    for (const MaterialMap& m : maps) references.push_back(as_metrics_image(m.image));
    std::vector<std::vector<ProxyScores>> scores(sides.size());
    const bool together = first.pixel_count() <= kProxiesTogetherPixels;
    parallel_for(together ? options.threads : 1, sides.size(), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (candidates[i].file.empty()) continue;
            const int side = std::min(kLargeProxySide, 2 * sides[i]);
            scores[i] = set_proxy_scores(maps, references, candidates[i].file, side, together ? 1 : options.threads);
        }
    });
    const int best = best_relative(scores);
    if (best < 0)
        fail_nothing_fits("atlas of the " + std::to_string(maps.size()) + " maps", options.budget);
    MaterialChoice chosen = std::move(candidates[std::size_t(best)]);
    chosen.attempts = 0;
    for (uint32_t a : attempts) chosen.attempts += a;
    return chosen;
}

}  // namespace

MaterialChoice choose_material_atlas(const std::vector<MaterialMap>& maps, const AtlasChoiceOptions& given) {
    const Image& first = maps.at(0).image;
    if (first.width < kMinAtlasSide || first.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an atlas needs maps of at least " + std::to_string(kMinAtlasSide) + "x" +
                                              std::to_string(kMinAtlasSide) + " pixels");
    // One synthesis reads every map, so the set wraps unless told when
    // every map's atlas would (ExampleTiling::wraps), with the period bar
    // unless a map repeats a tile.
    bool tiles = true, wraps = true, bar = true;
    for (const MaterialMap& m : maps) {
        const ExampleTiling t = example_tiling(m.image);
        tiles = tiles && t.tiles;
        wraps = wraps && t.wraps();
        bar = bar && t.period_bar();
    }
    AtlasChoiceOptions options = given;
    if (options.detect_tileable && !options.example_tileable) options.example_tileable = wraps;
    const GuideMatrix guide = guide_matrix(maps);
    // AV1's quantiser steps are in sample units, so at one level a map of
    // low contrast loses more of its structure than a contrasty one (a
    // wood gloss map at the albedo's level kept a correlation of 0.69 with
    // it where the example's is 0.98). Each map's level is lowered by 6
    // (about a halving of the step) per halving of its contrast against
    // the set's most contrasty map, by 24 at most (measured: at most 12
    // left that correlation at 0.88).
    std::vector<double> deviation;
    for (const MaterialMap& m : maps) deviation.push_back(std::max(map_contrast(m.image), kFlatDeviation));
    const double most = *std::max_element(deviation.begin(), deviation.end());
    std::vector<int> offsets;
    for (const double d : deviation)
        offsets.push_back(std::clamp(int(std::lround(6.0 * std::log2(d / most))), -24, 0));
    const std::vector<MapPrediction> predictions = fit_map_predictions(maps);
    if (options.compaction && first.pixel_count() > kLargeExamplePixels) {
        MaterialChoice c = choose_material_part(maps, guide, offsets, predictions, options);
        c.example_tiles = tiles;
        return c;
    }
    uint32_t attempts = 0;
    for (int scale = 16; scale >= 1; scale = scale == 16 ? 12 : scale * 3 / 4) {
        const int w = std::min({kMaxAtlasSide, first.width, std::max(kMinAtlasSide, first.width * scale / 16)});
        const int h = std::min({kMaxAtlasSide, first.height, std::max(kMinAtlasSide, first.height * scale / 16)});
        SetLevelSearch search(maps, guide, offsets, predictions, {0, 0, w, h}, options, options.threads, &attempts,
                              AtlasEncodeOptions{}.speed, bar);
        const int best = finest_fitting_level(options.budget, [&](int cq) { return search.size_at(cq); });
        if (best >= 0) {
            MaterialChoice c = search.choice(best);
            c.example_tiles = tiles;
            c.attempts = attempts;
            return c;
        }
        if ((w == kMinAtlasSide && h == kMinAtlasSide) || scale == 1) break;
    }
    fail_nothing_fits("atlas of the " + std::to_string(maps.size()) + " maps", options.budget);
}

}  // namespace vqtex
