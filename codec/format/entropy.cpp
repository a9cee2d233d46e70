// entropy.cpp - zstd section decoding (writer/zstd_compress.cpp codes them).
#include "format/entropy.hpp"

#include <zstd.h>

#include "common/error.hpp"

namespace vqtex {

std::vector<uint8_t> zstd_decompress(const uint8_t* data, std::size_t size, std::size_t raw_size,
                                     const std::string& what) {
    const unsigned long long declared = ZSTD_getFrameContentSize(data, size);
    if (declared == ZSTD_CONTENTSIZE_ERROR)
        fail(VQTEX_ERROR_CORRUPT, what + ": not a zstd frame");
    if (declared == ZSTD_CONTENTSIZE_UNKNOWN)
        fail(VQTEX_ERROR_CORRUPT, what + ": zstd frame does not declare its size");
    if (ZSTD_findFrameCompressedSize(data, size) != size)
        fail(VQTEX_ERROR_CORRUPT, what + ": must be exactly one zstd frame");
    if (declared != raw_size)
        fail(VQTEX_ERROR_CORRUPT, what + ": zstd frame holds " + std::to_string(declared) +
                                      " bytes, the section table says " + std::to_string(raw_size));
    std::vector<uint8_t> out(raw_size);
    // The destination is exactly raw_size bytes: a frame that would expand
    // further fails instead of allocating more.
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), data, size);
    if (ZSTD_isError(n)) fail(VQTEX_ERROR_CORRUPT, what + ": zstd error: " + ZSTD_getErrorName(n));
    if (n != raw_size)
        fail(VQTEX_ERROR_CORRUPT, what + ": decompressed to " + std::to_string(n) + " bytes, expected " +
                                      std::to_string(raw_size));
    return out;
}

}  // namespace vqtex
