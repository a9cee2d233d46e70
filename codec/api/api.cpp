// api.cpp - the exported C boundary every build has, the decoder's too:
// version, status messages, and releasing what the library handed out. No
// exception crosses the boundary; every failure becomes a status and a
// detail line (api_support.hpp).
#include <cstdlib>
#include <cstring>

#include "vqtex/vqtex.h"

extern "C" {

uint32_t vqtex_version(void) { return VQTEX_VERSION_NUMBER; }

const char* vqtex_version_string(void) {
#define VQTEX_STR2(x) #x
#define VQTEX_STR(x) VQTEX_STR2(x)
    return VQTEX_STR(VQTEX_VERSION_MAJOR) "." VQTEX_STR(VQTEX_VERSION_MINOR) "." VQTEX_STR(
        VQTEX_VERSION_PATCH);
}

const char* vqtex_status_message(vqtex_status status) {
    // A C caller may pass any int: read it as one (C++ may not load an enum
    // outside its range; UBSan reports it).
    int code;
    static_assert(sizeof code == sizeof status);
    std::memcpy(&code, &status, sizeof code);
    switch (code) {
        case VQTEX_OK: return "success";
        case VQTEX_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case VQTEX_ERROR_IMAGE_TOO_SMALL: return "example image too small for the neighbourhood";
        case VQTEX_ERROR_OUT_OF_MEMORY: return "out of memory";
        case VQTEX_ERROR_CANCELLED: return "cancelled";
        case VQTEX_ERROR_LIMIT_EXCEEDED: return "size limit exceeded";
        case VQTEX_ERROR_BAD_MAGIC: return "not a vqtex file (bad magic)";
        case VQTEX_ERROR_UNSUPPORTED_VERSION: return "unsupported format version";
        case VQTEX_ERROR_TRUNCATED: return "file is truncated";
        case VQTEX_ERROR_CHECKSUM: return "checksum mismatch";
        case VQTEX_ERROR_CORRUPT: return "corrupt file";
        case VQTEX_ERROR_INTERNAL: return "internal error";
    }
    return "unknown status";
}

void vqtex_image_free(vqtex_image* image) {
    if (!image) return;
    std::free(image->pixels);
    *image = vqtex_image{};
}

void vqtex_image16_free(vqtex_image16* image) {
    if (!image) return;
    std::free(image->pixels);
    *image = vqtex_image16{};
}

void vqtex_free(void* data) { std::free(data); }

void vqtex_volume_free(vqtex_volume* v) {
    if (!v) return;
    std::free(v->pixels);
    *v = vqtex_volume{};
}

}  // extern "C"
