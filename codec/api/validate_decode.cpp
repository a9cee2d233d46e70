// validate_decode.cpp - the checks of validate.hpp the decoder library
// needs: the decode params and what every params struct shares.
#include <string>

#include "api/api_support.hpp"
#include "api/validate.hpp"
#include "common/error.hpp"

namespace vqtex {

void check_struct_size(uint32_t struct_size, std::size_t expected, const char* type) {
    if (struct_size == expected) return;
    std::string detail = std::string(type) + " not initialised with " + type + "_init()";
    if (struct_size != 0)
        detail += " (its struct_size is " + std::to_string(struct_size) + ", this library's is " +
                  std::to_string(expected) + ": a caller built against another vqtex.h must be rebuilt)";
    fail(VQTEX_ERROR_INVALID_ARGUMENT, detail);
}

void check_output_side(uint32_t width, uint32_t height, uint32_t least) {
    if (width < least || height < least || width > kMaxOutputSide || height > kMaxOutputSide)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(width) + "x" + std::to_string(height) +
                                               " is out of range (1 to " +
                                               std::to_string(kMaxOutputSide) + " per side)");
}

void validate(const vqtex_decode_params* p) {
    if (!p) fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_decode_params not initialised with vqtex_decode_params_init()");
    check_struct_size(p->struct_size, sizeof(vqtex_decode_params), "vqtex_decode_params");
    check_output_side(p->width, p->height, 0);  // 0 = the example's size
}

}  // namespace vqtex
