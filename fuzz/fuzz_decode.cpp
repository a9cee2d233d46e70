// fuzz_decode.cpp - libFuzzer target: any bytes as a .vqt file through
// vqtex_decode_mips and vqtex_decode at a small output size and a low memory
// limit, so the fuzzer spends its time on the parser and the synthesis of
// what the parser accepts, not on large legitimate outputs; an animation
// (format 2 or 12) goes to vqtex_decode_volume for a few frames. Inputs whose
// only fault is the checksum are decoded again with the checksum repaired.
// Whatever decodes must have the right mip chain; one accepted input in
// kRecheck is decoded a second time, with vqtex_decode, which must give the
// chain's first level (decoding is deterministic). Decoding every accepted
// input twice halved the target's speed for no coverage: vqtex_decode_mips
// runs all of vqtex_decode's code.
#include "fuzz_support.hpp"

using namespace vqtex_fuzz;

namespace {

constexpr uint32_t kWidth = 24, kHeight = 20;
constexpr uint32_t kRecheck = 4;

vqtex_decode_params params() {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = kWidth;
    p.height = kHeight;
    p.threads = 1;
    p.memory_limit = 32u << 20;
    return p;
}

// FNV-1a: which inputs are decoded twice depends on their bytes alone, so a
// failure reproduces from the input.
uint32_t input_hash(const uint8_t* data, size_t size) {
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 16777619u;
    return h;
}

// An animation (format 2 or 12): a few small frames through
// vqtex_decode_volume, which must give exactly what it was asked for.
vqtex_status decode_animation(const uint8_t* data, size_t size) {
    // Two frames reach everything a longer output does (the first frame's
    // levels, a later frame's correction, the loop closing); small, as the
    // still decodes are, so that animations do not slow the target down.
    constexpr uint32_t kFrames = 2, kSide = 12;
    vqtex_decode_params p = params();
    p.width = kSide;
    p.height = kSide;
    vqtex_volume out;
    vqtex_error err;
    const vqtex_status st = vqtex_decode_volume(&p, kFrames, data, size, &out, &err);
    if (st != VQTEX_OK) {
        check_failure(st, err);
        if (out.pixels) violated("a failed animation decode returned frames");
        return st;
    }
    if (out.width != kSide || out.height != kSide || out.frames != kFrames || out.channels < 1 || out.channels > 4 ||
        !out.pixels)
        violated("decoded animation has the wrong shape");
    volatile uint32_t sum = 0;
    for (size_t i = 0; i < size_t(kSide) * kSide * kFrames * out.channels; ++i) sum = sum + out.pixels[i];
    vqtex_volume_free(&out);
    return st;
}

vqtex_status decode(const uint8_t* data, size_t size) {
    const vqtex_decode_params p = params();
    vqtex_image levels[16];
    uint32_t count = 0;
    vqtex_error err;
    const vqtex_status st = vqtex_decode_mips(&p, data, size, levels, 16, &count, &err);
    // An animation is refused as a still texture before anything else:
    // decode its frames instead.
    if (st == VQTEX_ERROR_INVALID_ARGUMENT && size > 9 && (data[8] == 2 || data[8] == 12) && data[9] == 0)
        return decode_animation(data, size);
    if (st != VQTEX_OK) {
        check_failure(st, err);
        if (count != 0) violated("a failed decode returned levels");
        return st;
    }
    if (count < 2 || levels[0].width != kWidth || levels[0].height != kHeight || levels[count - 1].width != 1 ||
        levels[count - 1].height != 1)
        violated("mip chain has the wrong shape");
    if (levels[0].channels < 1 || levels[0].channels > 4) violated("decoded image is malformed");
    for (uint32_t i = 0; i < count; ++i) {
        if (!levels[i].pixels || levels[i].channels != levels[0].channels) violated("mip level is malformed");
        touch(levels[i]);
    }

    if (input_hash(data, size) % kRecheck == 0) {
        // The texture alone is the chain's first level.
        vqtex_image out;
        if (vqtex_decode(&p, data, size, &out, &err) != VQTEX_OK)
            violated("decode_mips succeeded but decode failed", &err);
        if (out.width != kWidth || out.height != kHeight || out.channels != levels[0].channels || !out.pixels)
            violated("decoded image has another shape than the mip chain's first level");
        const size_t bytes = size_t(kWidth) * kHeight * out.channels;
        if (std::memcmp(levels[0].pixels, out.pixels, bytes) != 0)
            violated("decode and decode_mips disagree: decoding is not deterministic");
        vqtex_image_free(&out);
    }
    for (uint32_t i = 0; i < count; ++i) vqtex_image_free(&levels[i]);
    return st;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (decode(data, size) == VQTEX_ERROR_CHECKSUM) {
        const std::vector<uint8_t> repaired = with_valid_checksum(data, size);
        decode(repaired.data(), repaired.size());
    }
    return 0;
}
