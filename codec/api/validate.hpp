// validate.hpp - one validation function per params struct of the C API.
// Every exported entry point calls its struct's function first, before it
// reads an image or does any work, so a bad value is refused at once with a
// detail line naming the field and its range (as astc-encoder's config
// step). What can only be checked against the example (the pyramid depth it
// allows, the shapes that fit) is checked by the analysis when it plans.
// These are the decoder library's (validate_decode.cpp); validate_encode.hpp
// declares the ones only the full library (vqtex) has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>

#include "common/error.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

// Whether an enum field holds one of `values`. A C caller may store any int
// in it, and C++ may not load an enum outside its range (UBSan reports it),
// so the field is read as the int it is.
template <typename Enum>
bool is_one_of(const Enum& field, std::initializer_list<Enum> values) {
    int raw;
    static_assert(sizeof raw == sizeof field);
    std::memcpy(&raw, &field, sizeof raw);
    for (Enum v : values)
        if (raw == int(v)) return true;
    return false;
}

// Refuses a params struct whose struct_size is not this header's: one its
// *_init function did not fill, or one from a caller built against another
// vqtex.h (its fields would be read at the wrong places).
void check_struct_size(uint32_t struct_size, std::size_t expected, const char* type);

// An output side, 1 (or 0 where 0 means the example's size) to the largest
// output the library writes.
void check_output_side(uint32_t width, uint32_t height, uint32_t least);

void validate(const vqtex_decode_params* p);

}  // namespace vqtex
