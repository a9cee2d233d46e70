// codec_support.hpp - helpers for the codec tests: encode and decode
// through the public API with small, fast settings.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/image.hpp"
#include "vqtex/vqtex.h"

namespace vqtex_test {

// Small settings that still exercise every section kind of the trees
// format (v1); the atlas formats (v3 to v7, v7 the default) have
// tests/test_atlas.cpp.
inline vqtex_encode_params fast_encode_params() {
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.codebook = VQTEX_CODEBOOK_TREES;
    p.quality = 10;
    vqtex_encode_params_preset(&p, 10);
    p.threads = 1;
    return p;
}

inline std::vector<uint8_t> encode(const vqtex::Image& ex, const vqtex_encode_params& p,
                                   vqtex_encode_stats* stats = nullptr) {
    vqtex_image in{uint32_t(ex.width), uint32_t(ex.height), uint32_t(ex.channels),
                   const_cast<uint8_t*>(ex.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    if (vqtex_encode(&p, &in, &data, &size, stats, &err) != VQTEX_OK)
        throw std::runtime_error(std::string("encode failed: ") + err.detail);
    std::vector<uint8_t> bytes(data, data + size);
    vqtex_free(data);
    return bytes;
}

// The status of an encode expected to fail, with its error; checks that it
// hands back no buffer.
inline vqtex_status encode_status(const vqtex::Image& ex, const vqtex_encode_params& p, vqtex_error* err) {
    vqtex_image in{uint32_t(ex.width), uint32_t(ex.height), uint32_t(ex.channels),
                   const_cast<uint8_t*>(ex.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    const vqtex_status st = vqtex_encode(&p, &in, &data, &size, nullptr, err);
    if (st == VQTEX_OK) vqtex_free(data);
    EXPECT_TRUE(st == VQTEX_OK || data == nullptr) << "a failed encode hands back no buffer";
    return st;
}

inline vqtex_decode_params decode_params(uint32_t w, uint32_t h, uint64_t seed = VQTEX_SEED_FROM_FILE,
                                         uint32_t threads = 1) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = w;
    p.height = h;
    p.seed = seed;
    p.threads = threads;
    return p;
}

// Decodes; on failure returns an empty image and the status in *status.
inline vqtex::Image decode(const std::vector<uint8_t>& bytes, const vqtex_decode_params& p,
                           vqtex_status* status = nullptr, vqtex_error* error = nullptr) {
    vqtex_image out{};
    vqtex_error local{};
    vqtex_error* err = error ? error : &local;
    const vqtex_status st = vqtex_decode(&p, bytes.data(), bytes.size(), &out, err);
    if (status) *status = st;
    if (st != VQTEX_OK) {
        if (!status) throw std::runtime_error(std::string("decode failed: ") + err->detail);
        return vqtex::Image();
    }
    vqtex::Image img(int(out.width), int(out.height), int(out.channels));
    std::memcpy(img.pixels.data(), out.pixels, img.byte_count());
    vqtex_image_free(&out);
    return img;
}

// FNV-1a 64 of a byte range: the golden hashes.
inline uint64_t fnv1a(const uint8_t* data, std::size_t n) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ data[i]) * 0x100000001B3ull;
    return h;
}

}  // namespace vqtex_test
