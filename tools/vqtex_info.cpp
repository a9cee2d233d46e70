// vqtex-info - verify a .vqt file and show what it holds and where its
// bytes go, through the public API only.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex_tools;

int main(int argc, char** argv) {
    CLI::App app{"vqtex-info: verify a .vqt file and print its contents and byte breakdown."};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::string input;
    bool json = false;
    app.add_option("input", input, ".vqt file")->required();
    app.add_flag("--json", json, "machine-readable output");
    CLI11_PARSE(app, argc, argv);
    try {
        const std::vector<uint8_t> bytes = load_bytes(input);
        vqtex_file_info info{};
        vqtex_error err{};
        if (vqtex_inspect(bytes.data(), bytes.size(), 0, &info, &err) != VQTEX_OK) {
            std::fprintf(stderr, "vqtex-info: error: %s: %s\n", input.c_str(), err.detail);
            return 1;
        }
        // Bytes per kind of section, all levels together.
        // Format v3 holds an atlas and the engine's parameters instead.
        const bool atlas = info.format_version == 3;
        const char* tree_kinds[] = {"LEVL", "HIST", "TOPO", "CODE", "ENTR"};
        const char* tree_meaning[] = {"level parameters", "noise histograms", "tree topology + leaf weights",
                                      "leaf codewords", "leaf entries (pixels + keys)"};
        const char* atlas_kinds[] = {"ATLS", "SYNP"};
        const char* atlas_meaning[] = {"atlas (AV1 image)", "synthesis parameters"};
        const char** kinds = atlas ? atlas_kinds : tree_kinds;
        const char** meaning = atlas ? atlas_meaning : tree_meaning;
        const int kind_count = atlas ? 2 : 5;
        uint64_t per_kind[5] = {}, overhead = info.file_bytes;
        for (uint32_t i = 0; i < info.section_count; ++i)
            for (int k = 0; k < kind_count; ++k)
                if (std::string(info.sections[i].tag) == kinds[k]) {
                    per_kind[k] += info.sections[i].stored_bytes;
                    overhead -= info.sections[i].stored_bytes;
                }
        if (json) {
            std::printf("{\"file\":%s,\"bytes\":%llu,\"format_version\":%u,\"exemplar_width\":%u,"
                        "\"exemplar_height\":%u,\"channels\":%u,\"levels\":%u,\"seam_closing\":%u,"
                        "\"precision\":%u,\"seed\":%llu,\"exemplar_frames\":%u,\"codewords\":[",
                        json_string(input).c_str(), (unsigned long long)info.file_bytes, info.format_version,
                        info.exemplar_width, info.exemplar_height, info.channels, info.levels, info.seam_closing,
                        info.precision, (unsigned long long)info.seed, info.exemplar_frames);
            for (uint32_t l = 0; l < info.levels; ++l) std::printf("%s%u", l ? "," : "", info.codewords[l]);
            std::printf("],\"sections\":[");
            for (uint32_t i = 0; i < info.section_count; ++i)
                std::printf("%s{\"tag\":\"%s\",\"level\":%u,\"kind\":%u,\"raw\":%llu,\"stored\":%llu}", i ? "," : "",
                            info.sections[i].tag, info.sections[i].level, info.sections[i].kind,
                            (unsigned long long)info.sections[i].raw_bytes,
                            (unsigned long long)info.sections[i].stored_bytes);
            std::printf("],\"header_and_checksum\":%llu}\n", (unsigned long long)overhead);
            return 0;
        }
        std::printf("%s: vqtex format %u, %llu bytes, checksum OK\n", input.c_str(), info.format_version,
                    (unsigned long long)info.file_bytes);
        std::printf("example   %ux%u, %u channel%s; default seed %llu\n", info.exemplar_width,
                    info.exemplar_height, info.channels, info.channels == 1 ? "" : "s",
                    (unsigned long long)info.seed);
        if (info.exemplar_frames) {
            std::printf("animation %u example frames; windows", info.exemplar_frames);
            for (uint32_t l = 0; l < info.levels; ++l)
                std::printf(" {%ux%ux%u,%u}", info.shapes[l].rows, info.shapes[l].cols, info.window_frames[l],
                            info.shapes[l].levels);
            std::printf(" (finest first)\n");
        }
        if (atlas)
            std::printf("decoding  coherent engine, %u levels, an atlas of %u pixels\n", info.levels, info.codewords[0]);
        else
            std::printf("decoding  %u levels, %s init, backtrack %u, seam closing %s, %u-bit codewords, %u-bit pixels\n",
                        info.levels, info.init ? "noise" : "parent", info.backtrack, info.seam_closing ? "on" : "off",
                        info.precision, info.pixel_precision);
        for (uint32_t l = 0; l < info.levels && !atlas; ++l)
            std::printf("  level %u  {%ux%u,%u}  %5u codewords  %6u entries  %5u closing codewords\n", l,
                        info.shapes[l].rows, info.shapes[l].cols, info.shapes[l].levels, info.codewords[l],
                        info.entries[l], info.closing_codewords[l]);
        std::printf("bytes by section kind (stored, with section headers):\n");
        for (int k = 0; k < kind_count; ++k)
            std::printf("  %s  %-32s %8llu  %5.1f%%\n", kinds[k], meaning[k], (unsigned long long)per_kind[k],
                        100.0 * double(per_kind[k]) / double(info.file_bytes));
        std::printf("  ----  %-32s %8llu  %5.1f%%\n", "file header and checksum", (unsigned long long)overhead,
                    100.0 * double(overhead) / double(info.file_bytes));
        std::printf("sections:\n");
        for (uint32_t i = 0; i < info.section_count; ++i)
            std::printf("  %s level %u %-8s raw %8llu  stored %8llu\n", info.sections[i].tag, info.sections[i].level,
                        info.sections[i].kind == 2 ? "seam" : info.sections[i].kind ? "closing" : "", (unsigned long long)info.sections[i].raw_bytes,
                        (unsigned long long)info.sections[i].stored_bytes);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-info: error: %s\n", e.what());
        return 1;
    }
}
