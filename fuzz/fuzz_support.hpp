// fuzz_support.hpp - what the libFuzzer targets share: the properties every
// public call must keep on hostile input (a known status with a one-line
// detail, never an internal error or an allocation failure past the memory
// limit), and the checksum repair that lets mutated files reach the parser.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "vqtex/vqtex.h"

namespace vqtex_fuzz {

// Stops the run with a report libFuzzer records as a crash.
[[noreturn]] inline void violated(const char* what, const vqtex_error* err = nullptr) {
    std::fprintf(stderr, "vqtex fuzz: property violated: %s%s%s\n", what, err ? ": " : "",
                 err ? err->detail : "");
    std::abort();
}

// A failure must be one of the documented statuses for bad data, with a
// NUL-terminated, non-empty detail. INTERNAL means a case nobody checked;
// OUT_OF_MEMORY means an allocation the memory limit should have refused.
inline void check_failure(vqtex_status st, const vqtex_error& err) {
    if (err.status != st) violated("error.status differs from the returned status", &err);
    if (std::memchr(err.detail, '\0', sizeof err.detail) == nullptr) violated("detail is not NUL-terminated");
    if (err.detail[0] == '\0') violated("error without a detail");
    switch (st) {
    case VQTEX_ERROR_INVALID_ARGUMENT:
    case VQTEX_ERROR_IMAGE_TOO_SMALL:
    case VQTEX_ERROR_LIMIT_EXCEEDED:
    case VQTEX_ERROR_BAD_MAGIC:
    case VQTEX_ERROR_UNSUPPORTED_VERSION:
    case VQTEX_ERROR_TRUNCATED:
    case VQTEX_ERROR_CHECKSUM:
    case VQTEX_ERROR_CORRUPT:
        return;
    default:
        violated("unexpected status for bad input", &err);
    }
}

// The file format's CRC-32 (IEEE 802.3, reflected; docs/FORMAT.md §1),
// bit by bit: the targets see the library through its public API only, and
// the checksum's speed does not matter here.
inline uint32_t crc32(const uint8_t* data, size_t size) {
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < size; ++i) {
        crc ^= data[i];
        for (int k = 0; k < 8; ++k) crc = (crc & 1u) ? 0xEDB88320u ^ (crc >> 1) : crc >> 1;
    }
    return ~crc;
}

// The file with its trailing CRC-32 made to match its bytes, so that a
// mutation inside the file is judged by the parser, not by the checksum.
inline std::vector<uint8_t> with_valid_checksum(const uint8_t* data, size_t size) {
    std::vector<uint8_t> bytes(data, data + size);
    if (bytes.size() < 4) return bytes;
    const uint32_t crc = crc32(bytes.data(), bytes.size() - 4);
    for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
    return bytes;
}

// Reads every pixel, so that a buffer smaller than its declared size is an
// AddressSanitizer report here rather than silent.
inline unsigned touch(const vqtex_image& img) {
    unsigned sum = 0;
    const size_t n = size_t(img.width) * img.height * img.channels;
    for (size_t i = 0; i < n; ++i) sum += img.pixels[i];
    return sum;
}

}  // namespace vqtex_fuzz
