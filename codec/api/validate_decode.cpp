// validate_decode.cpp - the checks of validate.hpp: the decoder library's
// params and the output size every synthesis shares.
#include "api/validate.hpp"

#include <string>

#include "api/api_support.hpp"
#include "common/error.hpp"

namespace vqtex {

void check_output_side(uint32_t width, uint32_t height, uint32_t least) {
    if (width < least || height < least || width > kMaxOutputSide || height > kMaxOutputSide)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(width) + "x" + std::to_string(height) +
                                               " is out of range (1 to " +
                                               std::to_string(kMaxOutputSide) + " per side)");
}

void validate(const vqtex_decode_params* p) {
    if (!p || p->struct_size != sizeof(vqtex_decode_params))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_decode_params not initialised with vqtex_decode_params_init()");
    check_output_side(p->width, p->height, 0);  // 0 = the example's size
}

}  // namespace vqtex
