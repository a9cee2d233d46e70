// fuzz_encode.cpp - libFuzzer target: the encoder on small images whose
// size, channels, pixels and parameters all come from the input bytes
// (sizes down to 1x1, out-of-range parameters included). Whatever the
// encoder accepts must make a file that inspects and decodes.
//
// Input layout: 16 parameter bytes (below), then pixel bytes, repeated as
// needed to fill the image.
#include "fuzz_support.hpp"

using namespace vqtex_fuzz;

namespace {

struct Bytes {
    const uint8_t* data;
    size_t size, pos = 0;
    uint8_t next() { return pos < size ? data[pos++] : 0; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Bytes in{data, size};
    const uint32_t width = 1 + in.next() % 33, height = 1 + in.next() % 33;
    const uint32_t channels = in.next() % 6;  // 0 and 5 are invalid on purpose
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    const int quality = in.next() % 101;
    p.quality = uint32_t(quality);
    vqtex_encode_params_preset(&p, quality);
    p.threads = 1;
    p.levels = in.next() % 6;  // 0 = automatic, 5 is too many for tiny images
    const uint8_t shape = in.next();
    if (shape & 0x80) {
        // Any window, odd or not: the encoder must refuse what it cannot code.
        p.trees.shapes[0] = vqtex_shape{uint8_t(shape % 8), uint8_t((shape >> 3) % 8), uint8_t(1 + (shape >> 6) % 2)};
        p.trees.shapes[1] = vqtex_shape{0, 0, 0};
    }
    const uint8_t codewords = in.next();
    if (codewords) p.trees.tsvq.codewords[0] = codewords;
    p.trees.tsvq.entries_per_leaf = in.next() % 70;  // above 64 is invalid
    const uint8_t flags = in.next();
    p.trees.tsvq.no_entry_keys = flags & 1;
    p.trees.tsvq.seam_closing = (flags >> 1) & 1;
    p.example_tileable = (flags >> 2) & 1;
    p.trees.tsvq.leaf = (flags >> 3) & 1 ? VQTEX_LEAF_CENTROID : VQTEX_LEAF_MEDOID;
    p.trees.init = (flags >> 4) & 1 ? VQTEX_INIT_NOISE : VQTEX_INIT_PARENT;
    p.trees.tsvq.closing_divisor = (flags >> 5) % 4;
    // Both file kinds: the atlas (the default) and the trees.
    p.codebook = (flags >> 7) & 1 ? VQTEX_CODEBOOK_TREES : VQTEX_CODEBOOK_ATLAS;
    p.trees.tsvq.closing_window = in.next() % 8;
    const uint8_t precision = in.next();
    if (precision & 0x80) {
        p.trees.precision = precision % 10;
        p.trees.pixel_precision = (precision >> 4) % 10;
    }
    p.trees.smoothing = 1 + in.next() % 4;
    p.trees.backtrack = 1 + in.next() % 4;
    p.trees.tsvq.train_fraction = float(1 + in.next() % 4) / 4.0f;
    in.next();  // reserved
    in.next();  // reserved

    const size_t pixel_bytes = size_t(width) * height * (channels ? channels : 1);
    std::vector<uint8_t> pixels(pixel_bytes, 0);
    const size_t available = in.size - in.pos;
    for (size_t i = 0; i < pixel_bytes && available; ++i) pixels[i] = data[in.pos + i % available];
    const vqtex_image example{width, height, channels, pixels.data()};

    uint8_t* file = nullptr;
    size_t file_size = 0;
    vqtex_encode_stats stats;
    vqtex_error err;
    const vqtex_status st = vqtex_encode(&p, &example, &file, &file_size, &stats, &err);
    if (st != VQTEX_OK) {
        check_failure(st, err);
        if (file) violated("a failed encode returned data");
        return 0;
    }
    if (!file || file_size != stats.bytes) violated("encode returned no data or the wrong size");

    vqtex_file_info info;
    if (vqtex_inspect(file, file_size, 0, &info, &err) != VQTEX_OK) violated("encoded file does not inspect", &err);
    if (info.exemplar_width != width || info.exemplar_height != height || info.channels != channels)
        violated("encoded file describes another example");
    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    dp.width = 1 + (width * 7) % 23;
    dp.height = 1 + (height * 5) % 19;
    dp.threads = 1;
    vqtex_image out;
    if (vqtex_decode(&dp, file, file_size, &out, &err) != VQTEX_OK) violated("encoded file does not decode", &err);
    if (out.width != dp.width || out.height != dp.height || out.channels != channels)
        violated("decoded image has the wrong shape");
    touch(out);
    vqtex_image_free(&out);
    vqtex_free(file);
    return 0;
}
