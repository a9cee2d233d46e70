// entropy.hpp - entropy coding of file sections with zstd. The only file
// that includes <zstd.h>.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vqtex {

std::vector<uint8_t> zstd_compress(const std::vector<uint8_t>& raw, int level);

// Decompresses exactly `raw_size` bytes; anything else (a frame declaring
// another size, a damaged frame, trailing data) is a corrupt-file error
// naming `what`. raw_size has been checked against the memory cap already.
std::vector<uint8_t> zstd_decompress(const uint8_t* data, std::size_t size, std::size_t raw_size,
                                     const std::string& what);

}  // namespace vqtex
