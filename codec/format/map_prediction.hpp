// map_prediction.hpp - one map of a set predicted from an earlier map
// (docs/FORMAT.md §4.17): predictive coding across the maps of a material,
// as AV1 predicts chroma from luma inside one image. A gloss or roughness
// map is often nearly a linear function of the albedo (the corpus's wood
// gloss: 0.983 correlated, 0.29 levels left over of 1.9); coded on its own
// at the set's level of distortion it keeps its few levels of contrast
// badly, and its correlation with the albedo drops (to 0.916). Coded as
// what the albedo does not predict, it costs almost nothing and follows
// the decoded albedo. Integer arithmetic, so the decoder is exact.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// Bounds a file's prediction fields must keep (§4.17): Q8 coefficients and
// offsets in 1/256.
inline constexpr int kMaxPredictionCoefficient = 4096;
inline constexpr int kMaxPredictionOffset = 1 << 20;

// Map m predicted from the earlier map `source`: channel c of the
// prediction is clamp((sum over k of coefficients[c * S + k] * s_k +
// offsets[c] + 128) >> 8, 0, 255), s the source map's S channel values; the
// map's coded samples r hold clamp(v - prediction + 128, 0, 255), and it
// decodes as clamp(r + prediction - 128, 0, 255). Both maps are 8-bit.
struct MapPrediction {
    int source = -1;  // -1: the map is coded as it is
    std::vector<int32_t> coefficients;
    std::vector<int32_t> offsets;

    bool predicted() const { return source >= 0; }
};

// The prediction of every pixel of a map of `channels` channels from
// `source` (of the same size).
Image predict_map(const Image& source, const MapPrediction& prediction, int channels);

// `coded` (the decoded residual) turned back into the map, in place.
void add_prediction(Image& coded, const Image& prediction);

}  // namespace vqtex
