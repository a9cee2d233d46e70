// validate.hpp - one validation function per params struct of the C API.
// Every exported entry point calls its struct's function first, before it
// reads an image or does any work, so a bad value is refused at once with a
// detail line naming the field and its range (as astc-encoder's config
// step). What can only be checked against the example (the pyramid depth it
// allows, the shapes that fit) is checked by the analysis when it plans.
#pragma once

#include "vqtex/vqtex.h"

namespace vqtex {

void validate(const vqtex_model_params& p);
void validate(const vqtex_synth_params* p);
// The synthesis of an animation of `frames` frames (0 = the example's count).
void validate_volume_synthesis(const vqtex_synth_params* p, uint32_t frames);
void validate(const vqtex_encode_params* p);
void validate(const vqtex_volume_encode_params* p);
void validate(const vqtex_fill_params* p);
void validate(const vqtex_decode_params* p);

}  // namespace vqtex
