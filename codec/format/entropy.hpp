// entropy.hpp - entropy decoding of file sections with zstd. The decoder
// library's only file that includes <zstd.h> (writer/zstd_compress.hpp is
// the encoder's).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vqtex {

// Decompresses exactly `raw_size` bytes; anything else (a frame declaring
// another size, a damaged frame, trailing data) is a corrupt-file error
// naming `what`. raw_size has been checked against the memory cap already.
std::vector<uint8_t> zstd_decompress(const uint8_t* data, std::size_t size, std::size_t raw_size,
                                     const std::string& what);

}  // namespace vqtex
