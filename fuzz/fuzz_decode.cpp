// fuzz_decode.cpp - libFuzzer target: any bytes as a .vqt file through
// vqtex_decode and vqtex_decode_mips at a small output size and a low memory
// limit, so the fuzzer spends its time on the parser and the synthesis of
// what the parser accepts, not on large legitimate outputs. Inputs whose
// only fault is the checksum are decoded again with the checksum repaired.
// Whatever decodes must decode the same twice and agree with the mip chain.
#include "fuzz_support.hpp"

using namespace vqtex_fuzz;

namespace {

constexpr uint32_t kWidth = 24, kHeight = 20;

vqtex_decode_params params() {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = kWidth;
    p.height = kHeight;
    p.threads = 1;
    p.memory_limit = 32u << 20;
    return p;
}

vqtex_status decode(const uint8_t* data, size_t size) {
    const vqtex_decode_params p = params();
    vqtex_image out;
    vqtex_error err;
    const vqtex_status st = vqtex_decode(&p, data, size, &out, &err);
    if (st != VQTEX_OK) {
        check_failure(st, err);
        if (out.pixels) violated("a failed decode returned pixels");
        return st;
    }
    if (out.width != kWidth || out.height != kHeight) violated("decoded image has another size");
    if (out.channels < 1 || out.channels > 4 || !out.pixels) violated("decoded image is malformed");
    touch(out);

    // The mip chain's first level is the same texture.
    vqtex_image levels[16];
    uint32_t count = 0;
    const vqtex_status mst = vqtex_decode_mips(&p, data, size, levels, 16, &count, &err);
    if (mst != VQTEX_OK) violated("decode succeeded but decode_mips failed", &err);
    if (count < 2 || levels[0].width != kWidth || levels[count - 1].width != 1 || levels[count - 1].height != 1)
        violated("mip chain has the wrong shape");
    const size_t bytes = size_t(kWidth) * kHeight * out.channels;
    if (levels[0].channels != out.channels || std::memcmp(levels[0].pixels, out.pixels, bytes) != 0)
        violated("decode and decode_mips disagree: decoding is not deterministic");
    for (uint32_t i = 0; i < count; ++i) {
        touch(levels[i]);
        vqtex_image_free(&levels[i]);
    }
    vqtex_image_free(&out);
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
