// zstd_compress.cpp - zstd section coding at the encoder's level.
#include "writer/zstd_compress.hpp"

#include <string>

#include <zstd.h>

#include "common/error.hpp"

namespace vqtex {

std::vector<uint8_t> zstd_compress(const std::vector<uint8_t>& raw, int level) {
    std::vector<uint8_t> out(ZSTD_compressBound(raw.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), level);
    if (ZSTD_isError(n)) fail(VQTEX_ERROR_INTERNAL, std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
}

}  // namespace vqtex
