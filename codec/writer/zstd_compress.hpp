// zstd_compress.hpp - entropy coding of file sections with zstd, what
// format/entropy.hpp decodes. Its .cpp is the only writer that includes
// <zstd.h>.
#pragma once

#include <cstdint>
#include <vector>

namespace vqtex {

std::vector<uint8_t> zstd_compress(const std::vector<uint8_t>& raw, int level);

}  // namespace vqtex
