// imageio_module.hpp - the interface between the programs and vqtex_imageio,
// the loadable module that holds every call into OpenImageIO. The programs
// do not link OpenImageIO: linking it costs about 0.3 s of dynamic loading
// (about 260 shared libraries) at every start, before any work. image_io.cpp
// loads the module with dlopen the first time a program reads or writes an
// image, so `vqtex-info`, `--help` and argument errors never pay for it.
//
// Both sides are built by the same CMake project with the same compiler, so
// the interface passes C++ types; `abi` guards against a module left over
// from another build. Module functions report failure by throwing
// std::runtime_error with a one-line message.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "image_io.hpp"

namespace vqtex_tools {

// Raise whenever ImageioModule or a type it passes changes.
constexpr uint32_t kImageioAbi = 3;

// One image to write: 8-bit samples in `pixels`, or 16-bit ones in
// `pixels16` when that is not null.
struct ImageLevel {
    uint32_t width = 0, height = 0, channels = 0;
    const uint8_t* pixels = nullptr;
    const uint16_t* pixels16 = nullptr;
};

struct ImageioModule {
    uint32_t abi;
    // One image, 1 to 4 channels (the first subimage), as `options` say.
    LoadedImage (*read)(const std::string& path, const ReadOptions& options);
    // Whether the format named by `name`'s extension keeps MIP levels in
    // one file; throws for an extension no format claims.
    bool (*supports_mipmap)(const std::string& name);
    // Writes `count` levels (more than one only where supports_mipmap) to
    // `file` in the format of `name`'s extension, with samples that stand
    // for `space`; every level has the same sample size. Leaves a partial
    // `file` on failure: the caller writes to a temporary name and removes it.
    WrittenImage (*write)(const std::string& name, const std::string& file, const ImageLevel* levels, uint32_t count,
                          const WriteOptions& options, SampleSpace space);
    // Images in a multi-image file (TIFF pages, GIF frames); 0 when it is
    // not an image OpenImageIO reads.
    int (*subimage_count)(const std::string& path);
    // Calls `each` with every image of a multi-image file in order, as
    // 8-bit colour.
    void (*read_subimages)(const std::string& path, const std::function<void(LoadedImage&&)>& each);
};

// The module, loaded on the first call (image_io.cpp); throws a one-line
// reason when it cannot be found or loaded.
const ImageioModule& imageio();

}  // namespace vqtex_tools

// The module's one exported symbol.
extern "C" const vqtex_tools::ImageioModule* vqtex_imageio_module();
