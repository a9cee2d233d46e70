// encode_support.hpp - what the encoder library's C functions share beside
// api_support.hpp: the file coder's settings for the caller's params.
#pragma once

#include <cstdint>

#include "vqtex/vqtex.h"
#include "writer/model_writer.hpp"

namespace vqtex {

// How the file coder should write what the caller asked for.
inline EncodeSettings encode_settings_of(const vqtex_encode_params& p) {
    EncodeSettings s;
    s.precision = int(p.precision);
    s.pixel_precision = int(p.pixel_precision);
    s.smoothing = int(p.smoothing);
    s.backtrack = uint8_t(p.backtrack);
    s.init = p.init == VQTEX_INIT_NOISE ? LevelInit::Noise : LevelInit::Parent;
    s.seed = p.seed;
    return s;
}

}  // namespace vqtex
