// material_encode_api.cpp - the exported encoder of a set of maps of one
// surface (docs/FORMAT.md §2, §4.15): the maps checked, their guide and
// atlas chosen by analysis/material_choice.cpp, one version 9 file written.
// Decoding is in decode_api.cpp (vqtex_decode_maps).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "analysis/material_choice.hpp"
#include "api/api_support.hpp"
#include "api/encode_support.hpp"
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

// The weight a map gets when the caller leaves it at 0: colour and
// height-like data shape a surface most, so they weigh twice the rest.
int default_weight(const vqtex_map& m, const std::string& name) {
    if (m.kind == VQTEX_MAP_COLOUR) return 2;
    if (m.kind == VQTEX_MAP_DATA) {
        std::string lower = name;
        for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
        for (const char* key : {"height", "disp", "bump"})
            if (lower.find(key) != std::string::npos) return 2;
    }
    return 1;
}

std::vector<MaterialMap> maps_from_c(const vqtex_map* maps, uint32_t count) {
    if (!maps || count == 0 || count > VQTEX_MAX_MAPS)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "a set holds 1 to " + std::to_string(VQTEX_MAX_MAPS) + " maps; " +
                                               (maps ? "got " + std::to_string(count) : std::string("maps is NULL")));
    std::vector<MaterialMap> out;
    std::set<std::string> names;
    for (uint32_t i = 0; i < count; ++i) {
        const vqtex_map& m = maps[i];
        const std::string where = "map " + std::to_string(i);
        if (!m.name || !is_map_name(m.name))
            fail(VQTEX_ERROR_INVALID_ARGUMENT, where + ": a name of 1 to " + std::to_string(VQTEX_MAX_MAP_NAME) +
                                                   " characters of [A-Za-z0-9_.-] is needed");
        const std::string name = m.name;
        if (!names.insert(name).second) fail(VQTEX_ERROR_INVALID_ARGUMENT, "two maps are named '" + name + "'");
        if (m.kind < VQTEX_MAP_COLOUR || m.kind > VQTEX_MAP_DATA)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "map '" + name + "': kind " + std::to_string(int(m.kind)) +
                                                   " is not colour, normal or data");
        if (m.weight > 8) fail(VQTEX_ERROR_INVALID_ARGUMENT, "map '" + name + "': weight above 8");
        MaterialMap mm;
        const int weight = m.weight ? int(m.weight) : default_weight(m, name);
        if (m.image16) {
            mm = map_from_16_bits(name, MapKind(m.kind), weight, image16_from_c(m.image16, "map image"));
        } else {
            mm.name = name;
            mm.kind = MapKind(m.kind);
            mm.weight = weight;
            mm.image = image_from_c(&m.image, "map image");
        }
        if (mm.kind == MapKind::Normal && mm.image.channels != 3)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "normal map '" + name + "' has " + std::to_string(mm.image.channels) +
                                                   " channels; a normal map is RGB (x, y, z)");
        if (!out.empty() && (mm.image.width != out[0].image.width || mm.image.height != out[0].image.height))
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "map '" + name + "' is " + std::to_string(mm.image.width) + "x" +
                                                   std::to_string(mm.image.height) + " but '" + out[0].name +
                                                   "' is " + std::to_string(out[0].image.width) + "x" +
                                                   std::to_string(out[0].image.height) +
                                                   ": the maps of a set have one size");
        out.push_back(std::move(mm));
    }
    return out;
}

}  // namespace

extern "C" {

vqtex_status vqtex_encode_maps(const vqtex_encode_params* params, const vqtex_map* maps, uint32_t count,
                               uint8_t** data, size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        clear_output(data, size);
        validate(params);
        if (params->codebook != VQTEX_CODEBOOK_ATLAS)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "a set of maps is stored as an atlas only: leave codebook at "
                                               "VQTEX_CODEBOOK_ATLAS (no --trees)");
        const auto t0 = std::chrono::steady_clock::now();
        const std::vector<MaterialMap> set = maps_from_c(maps, count);
        const ProgressFn progress = stage_progress(params->progress, params->progress_user, VQTEX_STAGE_ANALYSE);
        if (progress && !progress(0, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
        AtlasChoiceOptions o;
        // Each map a single image's budget at the quality (which counts at
        // most kBudgetedPixels, as for a single image), or the target size
        // shared.
        const uint64_t budgeted = std::min<uint64_t>(set[0].image.pixel_count(), kBudgetedPixels);
        o.budget = params->target_size
                       ? params->target_size
                       : atlas_budget_of_quality(int(params->quality), budgeted) * uint64_t(set.size());
        o.levels = int(params->levels);
        o.example_tileable = params->example_tileable == VQTEX_TILEABLE_YES;
        o.detect_tileable = params->example_tileable == VQTEX_TILEABLE_DETECT;
        o.seed = params->seed;
        o.threads = resolve_threads(params->threads);
        const MaterialChoice r = choose_material_atlas(set, o);
        if (progress && !progress(1, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
        copy_out(r.file, data, size);
        if (stats) {
            *stats = vqtex_encode_stats{};
            stats->bytes = r.file.size();
            stats->levels = uint32_t(r.levels);
            for (int l = 0; l < r.levels; ++l)
                stats->codewords[l] = uint32_t(uint64_t(r.atlas_width) * uint64_t(r.atlas_height));
            stats->quality = params->target_size ? 0u : params->quality;
            stats->attempts = r.attempts;
            stats->seconds = seconds_since(t0, std::chrono::steady_clock::now());
            stats->atlas_width = uint32_t(r.atlas_width);
            stats->atlas_height = uint32_t(r.atlas_height);
            stats->atlas_x = uint32_t(r.atlas_x);
            stats->atlas_y = uint32_t(r.atlas_y);
            stats->atlas_wraps = r.wraps ? 1u : 0u;
            stats->period_bar = r.period_bar ? 1u : 0u;
            stats->example_tiles = r.example_tiles ? 1u : 0u;
            stats->atlas_kind = r.atlas_width == set[0].image.width && r.atlas_height == set[0].image.height ? 0u : 1u;
        }
    });
}

}  // extern "C"
