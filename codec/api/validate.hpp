// validate.hpp - one validation function per params struct of the C API;
// here the decoder library's (validate_encode.hpp has the encoder
// library's). Every exported entry point calls its struct's function first,
// before it reads an image or does any work, so a bad value is refused at
// once with a detail line naming the field and its range (as astc-encoder's
// config step). What can only be checked against the example (the pyramid
// depth it allows, the shapes that fit) is checked by the analysis when it
// plans.
#pragma once

#include <cstdint>

#include "vqtex/vqtex.h"

namespace vqtex {

void validate(const vqtex_decode_params* p);

// An output size, 1 (or `least`) to kMaxOutputSide per side; `least` is 0
// where 0 means the example's size.
void check_output_side(uint32_t width, uint32_t height, uint32_t least);

}  // namespace vqtex
