// image_io.hpp - the tools' only door to image files: OpenImageIO reads
// whatever it can and converts to 8-bit; writes go to a temporary file that
// is renamed into place only on success, so a failure never leaves a partial
// output.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

struct LoadedImage {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
    std::string notice;  // non-empty when the file was converted (bit depth, channels)
};

// libpng and libjpeg print their own warnings and errors on stderr, and
// OpenImageIO repeats some; the tools promise a one-line error. While one of
// these lives, that text goes to a temporary file and is dropped: the reason
// is in the error vqtex reports.
class QuietStderr {
public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    std::FILE* file_ = nullptr;
    int saved_ = -1;
};

// Throws std::runtime_error with a one-line message naming the file.
LoadedImage load_image(const std::string& path);

// Writes 8-bit pixels; the format follows the file name's extension.
void save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                const uint8_t* pixels);

// Reads a whole file; throws with a one-line message naming it.
std::vector<uint8_t> load_bytes(const std::string& path);

// Writes a mip chain: one MIP-mapped file when the format supports it
// (TIFF, OpenEXR), else one file per level named STEM_mipN.EXT (level 0 is
// PATH itself). Returns the files written. All or nothing.
std::vector<std::string> save_mip_chain(const std::string& path, const vqtex_image* levels,
                                        uint32_t count);

// Writes bytes atomically (temporary file + rename).
void save_bytes(const std::string& path, const std::vector<uint8_t>& bytes);

// A temporary name beside `path` that keeps its extension.
std::string temporary_name_for(const std::string& path);

}  // namespace vqtex_tools
