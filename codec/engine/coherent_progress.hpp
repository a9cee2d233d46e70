// coherent_progress.hpp - the progress of the coherent engine's correction
// passes, for the caller's callback (which may cancel): the work is counted
// in pixels corrected, a level's area per pass, so that the engine for
// still textures and the one for animations report alike.
#pragma once

#include <cstdint>
#include <functional>

#include "common/error.hpp"
#include "engine/pyramid.hpp"
#include "vqtex/vqtex.h"

namespace vqtex::coherent {

// Pixels of level l of a width x height output.
inline uint64_t level_area(int width, int height, int l) {
    return uint64_t(pyramid_level_size(width, l)) * uint64_t(pyramid_level_size(height, l));
}

struct PassProgress {
    const std::function<bool(uint64_t done, uint64_t total)>& callback;
    uint64_t total = 0;
    uint64_t done = 0;

    // Counts `work` more pixels corrected; throws when the callback cancels.
    void add(uint64_t work) {
        done += work;
        if (callback && !callback(done, total)) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    }
};

}  // namespace vqtex::coherent
