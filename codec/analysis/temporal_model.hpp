// temporal_model.hpp - analysis of an example frame sequence into a
// VolumeModel: 3D pyramid, {RxCxD,k} shapes, noise histogram and TSVQ
// codebooks per level, trained on a random subset of the example's
// neighbourhoods (paper section 5.2: a random 10% by default).
#pragma once

#include <memory>
#include <vector>

#include "analysis/texture_model.hpp"
#include "engine/temporal_synthesis.hpp"
#include "tsvq/tsvq_tree.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

struct VolumeAnalysis {
    VolumeModel model;
    std::vector<std::shared_ptr<const Codebook>> codebooks;          // TSVQ only; [0] = finest
    std::vector<std::shared_ptr<const Codebook>> closing_codebooks;  // TSVQ with loop closing
    std::vector<std::shared_ptr<const Codebook>> seam_codebooks;     // TSVQ with frame-seam closing
    std::vector<std::size_t> training_vectors;
    std::size_t model_bytes = 0;
};

// params.seam_closing builds the loop-closing and frame-seam matchers; params.shapes is
// ignored (3D shapes come in `shapes`, [0] = finest, may be empty).
VolumeAnalysis analyse_volume(const Volume& example, const ModelParams& params,
                              const std::vector<Shape>& shapes, vqtex_search search, uint32_t backtrack,
                              int threads, const ProgressFn& progress);

}  // namespace vqtex
