// volume_encode_api.cpp - the exported encoder for animated textures (paper
// section 5.2 with the codec of section 6): a frame sequence into a file.
// Decoding is in decode_api.cpp. Validation and status mapping as in
// encode_api.cpp.
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>

#include "api/api_support.hpp"
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "analysis/temporal_model.hpp"
#include "api/encode_support.hpp"
#include "writer/volume_writer.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

extern "C" {

void vqtex_volume_encode_params_init(vqtex_volume_encode_params* p) {
    if (!p) return;
    *p = vqtex_volume_encode_params{};
    p->struct_size = sizeof(vqtex_volume_encode_params);
    vqtex_encode_params_init(&p->codec);
    p->codec.codebook = VQTEX_CODEBOOK_TREES;  // format 2: animations have no atlas yet
    // The paper's setting: codebooks from a random 10% of the example's
    // neighbourhoods; 3 levels (automatic_volume_levels).
    p->codec.model.levels = 0;
    p->codec.model.train_fraction = 0.1f;
}

vqtex_status vqtex_encode_volume(const vqtex_volume_encode_params* params, const vqtex_volume* example,
                                 uint8_t** data, size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!data || !size) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
        *data = nullptr;
        *size = 0;
        validate(params);
        const Volume ex = volume_from_c(example);
        const vqtex_encode_params& c = params->codec;
        std::vector<Shape> shapes;
        for (const vqtex_shape3& s : params->shapes)
            shapes.push_back(Shape{.rows = s.rows, .cols = s.cols, .levels = s.levels, .frames = s.frames});
        const auto t0 = std::chrono::steady_clock::now();
        const int threads = resolve_threads(c.threads);
        const VolumeAnalysis a = analyse_volume(ex, c.model, shapes, VQTEX_SEARCH_TSVQ, c.backtrack, threads,
                                                stage_progress(c.progress, c.progress_user, VQTEX_STAGE_ANALYSE));
        VolumeCodecModel model;
        model.channels = ex.channels;
        model.exemplar_width = uint32_t(ex.width);
        model.exemplar_height = uint32_t(ex.height);
        model.exemplar_frames = uint32_t(ex.frames);
        for (std::size_t l = 0; l < a.model.levels.size(); ++l) {
            VolumeCodecModel::Level lv;
            lv.shape = a.model.levels[l].shape;
            lv.histogram = a.model.levels[l].histogram;
            lv.causal = a.codebooks[l];
            lv.closing = a.closing_codebooks[l];
            lv.closing_shape = a.model.levels[l].closing_shape;
            lv.seam = a.seam_codebooks[l];
            lv.seam_shape = a.model.levels[l].seam_shape;
            model.levels.push_back(lv);
        }
        const std::vector<uint8_t> bytes = encode_volume_model(model, encode_settings_of(c));
        const auto t1 = std::chrono::steady_clock::now();
        copy_out(bytes, data, size);
        if (stats) {
            *stats = vqtex_encode_stats{};
            stats->bytes = bytes.size();
            stats->levels = uint32_t(a.codebooks.size());
            for (std::size_t l = 0; l < a.codebooks.size() && l < VQTEX_MAX_LEVELS; ++l) {
                stats->codewords[l] = uint32_t(a.codebooks[l]->leaf_count());
                stats->entries[l] = uint32_t(a.codebooks[l]->total_entries());
            }
            stats->attempts = 1;
            stats->seconds = std::chrono::duration<double>(t1 - t0).count();
        }
    });
}

}  // extern "C"
