// image_io.hpp - the tools' only door to image files: OpenImageIO reads
// whatever it can, as 8-bit samples or, when the caller keeps them, as
// 16-bit ones; writes go to a temporary file that is renamed into place only
// on success, so a failure never leaves a partial output. OpenImageIO itself
// lives in a module loaded on the first image read or write
// (imageio_module.hpp), so programs start fast.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

// What an image's samples stand for. It decides how they meet a file of
// floating-point samples (OpenEXR), whose convention is linear light, and
// which colour space the file's metadata names.
enum class SampleSpace {
    // sRGB-encoded colour; a 2- or 4-channel image's last channel is
    // straight alpha, which is never linearised. A float file holds linear
    // light (premultiplied in OpenEXR); metadata "sRGB" or "Linear".
    colour,
    // Values as they are (normal, roughness, height, mask maps): a float
    // file holds value / max, and no channel is alpha; metadata "Raw".
    data,
    // Whole numbers (vqtex_decode_coords' atlas positions), 2 channels
    // named x and y: a float file holds the numbers themselves; "Raw".
    positions,
};

struct LoadedImage {
    uint32_t width = 0, height = 0, channels = 0;
    uint32_t bits = 8;               // 8, or 16 (ReadOptions::keep_16 and a file of more than 8 bits)
    std::vector<uint8_t> pixels;     // bits 8
    std::vector<uint16_t> pixels16;  // bits 16
    std::string notice;  // non-empty when the file was converted (bit depth, channels, transfer curve)
};

// How an image is read.
struct ReadOptions {
    // colour: a float file's linear values are converted to the sRGB curve;
    // data: float values are taken as they are. Either way, float values
    // are clamped to 0..1 (the notice counts the samples clamped).
    SampleSpace space = SampleSpace::colour;
    // A file of more than 8 bits a sample (16-bit PNG/TIFF, half or float
    // OpenEXR) is read as 16 bits instead of being rounded to 8.
    bool keep_16 = false;
};

// What a write put in the file, for reports: the sample type the format
// took ("uint8", "uint16", "half", "float"; a format without 16-bit samples,
// such as JPEG, takes 8) and the colour space its metadata names.
struct WrittenImage {
    std::string samples;
    std::string colour_space;
};

// libpng and libjpeg print their own warnings and errors on stderr, and
// OpenImageIO repeats some; the tools promise a one-line error. While one of
// these lives, that text goes to a temporary file and is dropped: the reason
// is in the error vqtex reports. Threads may hold them at once (a batch
// reads and writes several files in parallel): the first one redirects
// file descriptor 2, the last one restores it, and the tools' own messages
// go through write_stderr, which reaches the real stderr meanwhile.
class QuietStderr {
public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;
};

// Writes text to the real stderr, even while a QuietStderr lives.
void write_stderr(const std::string& text);

// How images are written; set once, before any writing, by the program.
struct WriteOptions {
    // zlib level for PNG, 0 (fastest) to 9 (smallest). 1 by default: on
    // textures it writes several times faster than OpenImageIO's 6 for files
    // a few per cent larger (docs/PERFORMANCE.md, "Writing").
    int png_compression = 1;
};
void set_write_options(const WriteOptions& options);
const WriteOptions& write_options();

// Loads the image I/O module now if it is not loaded yet (reads and writes
// otherwise load it on first use), so that a caller can time the load
// apart from the work; throws the one-line reason when it cannot.
void load_image_io();

// Throws std::runtime_error with a one-line message naming the file. The
// first form reads 8-bit colour, as the programs that synthesise do.
LoadedImage load_image(const std::string& path);
LoadedImage load_image(const std::string& path, const ReadOptions& options);

// Writes 8-bit or 16-bit pixels; the format follows the file name's
// extension. PNG and TIFF keep 16-bit samples; OpenEXR takes half for 8-bit
// samples and float for 16-bit ones, in the space `space` says.
WrittenImage save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                        const uint8_t* pixels, SampleSpace space = SampleSpace::colour);
WrittenImage save_image16(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                          const uint16_t* pixels, SampleSpace space);

// The largest file load_bytes reads unless told otherwise: 1 GiB, far above
// any .vqt file (a 4096x4096 atlas coded near losslessly is tens of MB).
inline constexpr uint64_t kDefaultMaxFileBytes = uint64_t(1) << 30;

// Reads a whole file of at most `max_bytes` bytes, so that a huge file or a
// device such as /dev/zero is refused instead of filling memory; throws with
// a one-line message naming it.
// `raise` says how to read a larger one, if the tool has a way.
std::vector<uint8_t> load_bytes(const std::string& path, uint64_t max_bytes = kDefaultMaxFileBytes,
                                const std::string& raise = "");

// Throws "cannot write 'NAME': it is a folder" for the first of `names`
// that is a folder: a chain of files staged under temporary names checks
// every target with it before renaming any, so that a failed rename cannot
// leave part of the chain replaced.
void refuse_folders(const std::vector<std::string>& names);

// Writes a mip chain: one MIP-mapped file when the format supports it
// (TIFF, OpenEXR), else one file per level named STEM_mipN.EXT (level 0 is
// PATH itself). Returns the files written. All or nothing.
// `written`, when given, receives what the files hold.
std::vector<std::string> save_mip_chain(const std::string& path, const vqtex_image* levels, uint32_t count,
                                        SampleSpace space = SampleSpace::colour, WrittenImage* written = nullptr);

// Writes bytes atomically (temporary file + rename).
void save_bytes(const std::string& path, const std::vector<uint8_t>& bytes);

// A temporary name beside `path` that keeps its extension.
std::string temporary_name_for(const std::string& path);

}  // namespace vqtex_tools
