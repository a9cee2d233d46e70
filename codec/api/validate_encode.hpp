// validate_encode.hpp - the validation of the params structs only the full
// library (vqtex) takes (validate.hpp says how the checks are made and has the
// decoder's).
#pragma once

#include <cstdint>

#include "vqtex/vqtex.h"

namespace vqtex {

void validate(const vqtex_synth_params* p);
// The synthesis of an animation of `frames` frames (0 = the example's count).
void validate_volume_synthesis(const vqtex_synth_params* p, uint32_t frames);
void validate(const vqtex_encode_params* p);
void validate(const vqtex_volume_encode_params* p);
void validate(const vqtex_fill_params* p);

}  // namespace vqtex
