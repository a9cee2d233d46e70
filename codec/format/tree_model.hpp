// tree_model.hpp - a model as a file holds it, still or animated: per level
// the neighbourhood shapes, the noise histogram and the TSVQ trees.
// model_codec.hpp and volume_codec.hpp read these (writer/ writes them);
// texture_model_of and volume_model_of turn the trees into the TSVQ
// matchers the engine runs. Here, above both engine/ and tsvq/, because it
// needs both: the engine's shapes and histograms, and tsvq's trees.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/neighborhood.hpp"
#include "engine/neighborhood3d.hpp"
#include "engine/noise.hpp"
#include "tsvq/tsvq_tree.hpp"

namespace vqtex {

struct TextureModel;
struct VolumeModel;

// A still texture's model: per level, shape, histogram and codebooks.
struct CodecModel {
    int channels = 0;
    uint32_t exemplar_width = 0, exemplar_height = 0;
    struct Level {
        Shape shape;
        LevelHistogram histogram;  // empty when the file does not need it
        std::shared_ptr<const Codebook> causal;
        std::shared_ptr<const Codebook> closing;  // may be null
        Shape closing_shape;                      // symmetric; meaningful with `closing`
    };
    std::vector<Level> levels;  // [0] = finest
};

// An animated texture's model: the same with 3D shapes and the frame-seam tree.
struct VolumeCodecModel {
    int channels = 0;
    uint32_t exemplar_width = 0, exemplar_height = 0, exemplar_frames = 0;
    struct Level {
        Shape shape;
        LevelHistogram histogram;
        std::shared_ptr<const Codebook> causal;
        std::shared_ptr<const Codebook> closing;  // may be null
        Shape closing_shape;
        std::shared_ptr<const Codebook> seam;     // frame-seam closing: present with `closing`
        Shape seam_shape;
    };
    std::vector<Level> levels;  // [0] = finest
};

// Ready to synthesise: every tree becomes a TSVQ matcher that visits up to
// `backtrack` leaves per query.
TextureModel texture_model_of(const CodecModel& model, uint32_t backtrack);
VolumeModel volume_model_of(const VolumeCodecModel& model, uint32_t backtrack);

}  // namespace vqtex
