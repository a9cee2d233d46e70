// make_seeds.cpp - writes the fuzzers' seed corpora from the project's own
// corpus/ images, with the public API: valid .vqt files covering every
// format feature (keyed and keyless entries, noise and parent init, seam
// closing on and off, 1 to 4 channels, every precision; format v7 atlas
// files as the encoder writes them, the same as v3 to v6, and v7 files
// with a stored exemplar size and stored parameters; animations as
// space-time atlases and as trees), and encoder inputs
// in fuzz_encode.cpp's layout. Small crops keep the seeds small, which is
// what mutation works best on. Usage: make_seeds CORPUS_DIR OUT_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "common/checksum.hpp"
#include "atlas_v3_writer.hpp"
#include "engine/quilt.hpp"
#include "format/atlas_file.hpp"
#include "writer/atlas_writer.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"

namespace fs = std::filesystem;

namespace {

struct Variant {
    const char* name;
    int quality;
    bool keys, noise_init, closing;
    uint32_t levels, precision, closing_window, backtrack;
};

constexpr Variant kVariants[] = {
    {"q0", 0, false, false, true, 0, 0, 0, 2},
    {"q60keys", 60, true, false, true, 0, 0, 0, 2},
    {"noise", 30, false, true, false, 2, 0, 0, 1},
    {"q100", 100, false, false, true, 0, 8, 3, 3},
    {"keys1level", 20, true, true, true, 1, 2, 0, 1},
};

// Seed sizes. The fuzzer's speed is that of the inputs it keeps, which
// start as these: a v1/v2 file's trees grow with the example, and a v3
// decoder's analysis (PCA of every level) with the atlas's pixels and
// levels. 32x32 examples keep the 2-level pyramids the presets give 40x40
// ones (24x24 fell to 1 level); a 16x16 atlas has 3 levels, a 12x12 one 2
// (coherent_levels), so stacks deeper than 1 are still reached at a
// fraction of a 32x32 atlas's cost (4 levels).
constexpr uint32_t kSide = 32;
constexpr uint32_t kAtlasSides[] = {16, 12};

std::vector<uint8_t> crop(const vqtex_tools::LoadedImage& img, uint32_t side, uint32_t channels) {
    std::vector<uint8_t> out;
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x)
            for (uint32_t c = 0; c < channels; ++c)
                out.push_back(img.pixels[(size_t(y % img.height) * img.width + x % img.width) * img.channels +
                                         c % img.channels]);
    return out;
}

void write(const fs::path& path, const uint8_t* data, size_t size) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: make_seeds CORPUS_DIR OUT_DIR\n");
        return 2;
    }
    const fs::path corpus = argv[1], out = argv[2];
    fs::create_directories(out / "decode");
    fs::create_directories(out / "encode");
    const char* images[] = {"grey_noise_64.png", "leaves_rgba_64.png", "checks_p16_64.png", "weave_128.png",
                            "cellular_128.png"};
    int files = 0;
    for (size_t i = 0; i < std::size(images); ++i) {
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image((corpus / images[i]).string());
        const std::string stem = fs::path(images[i]).stem().string();
        // Channel counts cycle so that every count appears with every variant.
        for (size_t v = 0; v < std::size(kVariants); ++v) {
            const Variant& var = kVariants[v];
            const uint32_t channels = uint32_t(1 + (i + v) % 4), side = kSide;
            std::vector<uint8_t> pixels = crop(img, side, channels);
            vqtex_encode_params p;
            vqtex_encode_params_init(&p);
            p.quality = uint32_t(var.quality);
            vqtex_encode_params_preset(&p, var.quality);
            p.codebook = VQTEX_CODEBOOK_TREES;  // these are the v1 seeds (atlases: below, 16x16 and 12x12)
            p.threads = 1;
            p.trees.tsvq.no_entry_keys = var.keys ? 0 : 1;
            p.trees.tsvq.seam_closing = var.closing ? 1 : 0;
            p.levels = var.levels;
            p.trees.tsvq.closing_window = var.closing_window;
            p.trees.init = var.noise_init ? VQTEX_INIT_NOISE : VQTEX_INIT_PARENT;
            p.trees.backtrack = var.backtrack;
            if (var.precision) p.trees.precision = p.trees.pixel_precision = var.precision;
            const vqtex_image example{side, side, channels, pixels.data()};
            uint8_t* data = nullptr;
            size_t size = 0;
            vqtex_error err;
            if (vqtex_encode(&p, &example, &data, &size, nullptr, &err) != VQTEX_OK) {
                std::fprintf(stderr, "make_seeds: %s %s: %s\n", images[i], var.name, err.detail);
                return 1;
            }
            const std::string name = stem + "_" + var.name + "_c" + std::to_string(channels);
            write(out / "decode" / (name + ".vqt"), data, size);
            vqtex_free(data);
            // The same example and settings as a fuzz_encode input (16x16);
            // flag bit 7 asks for trees (every other variant, so that the
            // atlas encoder starts with seeds too).
            std::vector<uint8_t> input = {15, 15, uint8_t(channels), uint8_t(var.quality), uint8_t(var.levels), 0,
                                          0, uint8_t(var.keys ? 4 : 8),
                                          uint8_t((var.keys ? 0 : 1) | (var.closing ? 2 : 0) | (var.noise_init ? 16 : 0) | (v % 2 ? 0 : 128)),
                                          uint8_t(var.closing_window), 0, 0, uint8_t(var.backtrack - 1), 3, 0, 0};
            const std::vector<uint8_t> small = crop(img, 16, channels);
            input.insert(input.end(), small.begin(), small.end());
            write(out / "encode" / (name + ".bin"), input.data(), input.size());
            files += 2;
        }
    }
    // Atlas files: each channel count, a preset and a target size, as the
    // encoder writes them (v7), as v3 (ATLS and SYNP sections), as v4 (no
    // blend), as v5 (no relocation) and as v6 (no edge guard), so the
    // fuzzers reach every reader and dav1d; every other one also as a v7
    // file with the packed byte's optional fields, an exemplar size that
    // is not the atlas's and parameters that are not the defaults.
    for (size_t i = 0; i < std::size(images); ++i) {
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image((corpus / images[i]).string());
        const uint32_t channels = uint32_t(1 + i % 4), side = kAtlasSides[i % std::size(kAtlasSides)];
        std::vector<uint8_t> pixels = crop(img, side, channels);
        vqtex_encode_params p;
        vqtex_encode_params_init(&p);
        p.codebook = VQTEX_CODEBOOK_ATLAS;
        p.threads = 1;
        if (i % 2) p.target_size = 400;
        const vqtex_image example{side, side, channels, pixels.data()};
        uint8_t* data = nullptr;
        size_t size = 0;
        vqtex_error err;
        if (vqtex_encode(&p, &example, &data, &size, nullptr, &err) != VQTEX_OK) {
            std::fprintf(stderr, "make_seeds: %s atlas: %s\n", images[i], err.detail);
            return 1;
        }
        const std::string name = fs::path(images[i]).stem().string() + "_atlas_c" + std::to_string(channels);
        write(out / "decode" / (name + ".vqt"), data, size);
        try {
            const vqtex::AtlasFile f = vqtex::decode_atlas_file(data, size, 32u << 20);
            const std::vector<uint8_t> bits(data + f.bitstream_offset, data + f.bitstream_offset + f.atlas_bytes);
            const std::vector<uint8_t> v3 =
                vqtex::encode_atlas_file_v3(f.header, f.atlas.width, f.atlas.height, bits, f.params);
            write(out / "decode" / (name + "_v3.vqt"), v3.data(), v3.size());
            ++files;
            if (f.parameter_bytes == 0)
                for (uint8_t version : {uint8_t(4), uint8_t(5), uint8_t(6), uint8_t(7), uint8_t(8)}) {
                    // Versions 4 to 8: the same bytes with the version and
                    // the checksum made again (their default parameters
                    // have no blend, no relocation, no edge guard, no cuts
                    // or no covers).
                    std::vector<uint8_t> old(data, data + size);
                    old[8] = version;
                    const uint32_t crc = vqtex::crc32(old.data(), old.size() - 4);
                    for (int k = 0; k < 4; ++k) old[old.size() - 4 + std::size_t(k)] = uint8_t(crc >> (8 * k));
                    write(out / "decode" / (name + "_v" + std::to_string(version) + ".vqt"), old.data(), old.size());
                    ++files;
                }
            if (i % 2 == 0) {
                vqtex::FileHeader h = f.header;
                h.exemplar_width += 5;
                h.seed = 1000;
                vqtex::AtlasSynthesisParams sp;
                sp.example_tileable = true;
                sp.passes = 3;
                sp.coherence = 2;
                sp.jitter = 30;
                sp.blend = 3;
                sp.relocate = 16;
                sp.edge_guard = 3;
                const std::vector<uint8_t> v7 = vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, sp);
                write(out / "decode" / (name + "_fields.vqt"), v7.data(), v7.size());
                ++files;
                // Version 15: the same wrapping atlas with the period bar.
                vqtex::AtlasSynthesisParams barred = sp;
                barred.period_bar = true;
                const std::vector<uint8_t> v15 =
                    vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, barred);
                write(out / "decode" / (name + "_v15.vqt"), v15.data(), v15.size());
                ++files;
                // Versions 21, 20 and 19: the same atlas laid out by quilting,
                // its blocks in wavefront and in raster order, cut as planar
                // graphs or by maximum flow.
                vqtex::AtlasSynthesisParams quilted = sp;
                quilted.quilt = vqtex::quilt_block(f.atlas.width, f.atlas.height);
                if (quilted.quilt > 0) {
                    const std::vector<uint8_t> v19 =
                        vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, quilted);
                    write(out / "decode" / (name + "_v19.vqt"), v19.data(), v19.size());
                    quilted.quilt_wavefront = true;
                    const std::vector<uint8_t> v20 =
                        vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, quilted);
                    write(out / "decode" / (name + "_v20.vqt"), v20.data(), v20.size());
                    quilted.quilt_planar_cut = true;
                    const std::vector<uint8_t> v21 =
                        vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, quilted);
                    write(out / "decode" / (name + "_v21.vqt"), v21.data(), v21.size());
                    files += 3;
                }
                // Version 13: the atlas a part of a larger exemplar, its
                // origin stored.
                h.atlas_x = 3;
                h.atlas_y = 0;
                const std::vector<uint8_t> v13 = vqtex::encode_atlas_file(h, f.atlas.width, f.atlas.height, bits, sp);
                write(out / "decode" / (name + "_v13.vqt"), v13.data(), v13.size());
                ++files;
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "make_seeds: %s atlas: %s\n", images[i], e.what());
            return 1;
        }
        vqtex_free(data);
        ++files;
    }
    // Sets, so that the fuzzers reach the maps' reader, the guide and the
    // predictions: a colour map with a grey data map (its first channel,
    // so predicted: version 17, and 18 with an origin), and a normal map
    // alone (version 11, and 14).
    {
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image((corpus / images[0]).string());
        std::vector<uint8_t> colour = crop(img, 16, 3), grey = crop(img, 16, 1);
        const vqtex_image c{16, 16, 3, colour.data()}, g{16, 16, 1, grey.data()};
        const vqtex_map two[2] = {{"albedo", VQTEX_MAP_COLOUR, 0, c}, {"gloss", VQTEX_MAP_DATA, 0, g}};
        const vqtex_map one[1] = {{"normal", VQTEX_MAP_NORMAL, 0, c}};
        const std::pair<const vqtex_map*, uint32_t> sets[2] = {{two, 2}, {one, 1}};
        for (const auto& [maps, count] : sets) {
            vqtex_encode_params p;
            vqtex_encode_params_init(&p);
            p.threads = 1;
            p.target_size = 500;
            uint8_t* data = nullptr;
            size_t size = 0;
            vqtex_error err;
            if (vqtex_encode_maps(&p, maps, count, &data, &size, nullptr, &err) != VQTEX_OK) {
                std::fprintf(stderr, "make_seeds: set of %u maps: %s\n", count, err.detail);
                return 1;
            }
            write(out / "decode" / ("set_" + std::to_string(count) + "_maps.vqt"), data, size);
            // The same set as version 14: a part of a larger exemplar,
            // its origin stored.
            try {
                const vqtex::AtlasFile f = vqtex::decode_atlas_file(data, size, 32u << 20);
                // `coded` keeps the maps' predictions (versions 17, 18), `plain`
                // drops them (a residual is an image like any other).
                std::vector<vqtex::CodedMap> coded, plain;
                std::size_t at = f.bitstream_offset;
                for (const vqtex::AtlasMap& m : f.maps) {
                    coded.push_back({m.name, m.kind, m.atlas.channels, m.bits,
                                     std::vector<uint8_t>(data + at, data + at + m.bytes), m.prediction});
                    plain.push_back({m.name, m.kind, m.atlas.channels, m.bits,
                                     std::vector<uint8_t>(data + at, data + at + m.bytes), vqtex::MapPrediction{}});
                    at += m.bytes;
                }
                vqtex::FileHeader h = f.header;
                // Version 16: the set wrapping, with the period bar.
                vqtex::AtlasSynthesisParams barred = f.params;
                barred.example_tileable = true;
                barred.period_bar = true;
                const std::vector<uint8_t> v16 =
                    vqtex::encode_material_file(h, f.atlas.width, f.atlas.height, plain, f.guide, barred);
                write(out / "decode" / ("set_" + std::to_string(count) + "_maps_v16.vqt"), v16.data(), v16.size());
                ++files;
                h.exemplar_width += 4;
                h.exemplar_height += 2;
                h.atlas_x = 4;
                h.atlas_y = 1;
                const std::vector<uint8_t> v14 =
                    vqtex::encode_material_file(h, f.atlas.width, f.atlas.height, coded, f.guide, f.params);
                write(out / "decode" / ("set_" + std::to_string(count) + "_maps_v" +
                                        std::to_string(vqtex::read_format_version(v14.data(), v14.size())) + ".vqt"),
                      v14.data(), v14.size());
                ++files;
            } catch (const std::exception& e) {
                std::fprintf(stderr, "make_seeds: set of %u maps as version 14: %s\n", count, e.what());
                return 1;
            }
            vqtex_free(data);
            ++files;
        }
    }
    // Animations: a space-time atlas (version 22) of 1, 3 and 4 channels
    // and a trees file (version 2), 16x16 and 4 frames, so that the fuzzers
    // reach the sequence reader, dav1d's inter frames and both engines for
    // animations.
    for (uint32_t channels : {1u, 3u, 4u}) {
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image((corpus / images[channels % 5]).string());
        std::vector<uint8_t> frames;
        for (uint32_t t = 0; t < 4; ++t) {
            // Each frame the example moved 2 pixels to the right.
            const std::vector<uint8_t> frame = crop(img, 16 + 2 * t, channels);
            for (uint32_t y = 0; y < 16; ++y)
                for (uint32_t x = 0; x < 16; ++x)
                    for (uint32_t c = 0; c < channels; ++c)
                        frames.push_back(frame[(size_t(y) * (16 + 2 * t) + x + 2 * t) * channels + c]);
        }
        for (const vqtex_codebook codebook : {VQTEX_CODEBOOK_ATLAS, VQTEX_CODEBOOK_TREES}) {
            if (codebook == VQTEX_CODEBOOK_TREES && channels != 3) continue;
            vqtex_volume_encode_params p;
            vqtex_volume_encode_params_init(&p);
            p.codebook = codebook;
            p.threads = 1;
            if (codebook == VQTEX_CODEBOOK_ATLAS) p.target_size = 600;
            const vqtex_volume example{16, 16, 4, channels, frames.data()};
            uint8_t* data = nullptr;
            size_t size = 0;
            vqtex_error err;
            if (vqtex_encode_volume(&p, &example, &data, &size, nullptr, &err) != VQTEX_OK) {
                std::fprintf(stderr, "make_seeds: animation of %u channels: %s\n", channels, err.detail);
                return 1;
            }
            const std::string name = std::string("anim_") + (codebook == VQTEX_CODEBOOK_ATLAS ? "v22" : "v2") + "_c" +
                                     std::to_string(channels);
            write(out / "decode" / (name + ".vqt"), data, size);
            vqtex_free(data);
            ++files;
        }
    }
    std::printf("make_seeds: wrote %d seed files under %s\n", files, out.string().c_str());
    return 0;
}
