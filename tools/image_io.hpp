// image_io.hpp - the tools' only door to image files: OpenImageIO reads
// whatever it can and converts to 8-bit; writes go to a temporary file that
// is renamed into place only on success, so a failure never leaves a partial
// output.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vqtex_tools {

struct LoadedImage {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
    std::string notice;  // non-empty when the file was converted (bit depth, channels)
};

// Throws std::runtime_error with a one-line message naming the file.
LoadedImage load_image(const std::string& path);

// Writes 8-bit pixels; the format follows the file name's extension.
void save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                const uint8_t* pixels);

// Writes bytes atomically (temporary file + rename).
void save_bytes(const std::string& path, const std::vector<uint8_t>& bytes);

// A temporary name beside `path` that keeps its extension.
std::string temporary_name_for(const std::string& path);

}  // namespace vqtex_tools
