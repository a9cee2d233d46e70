// vqtex-info - verify a .vqt file and show what it holds and where its
// bytes go, through the public API only. Reads no image, so it never loads
// the image I/O module and starts in milliseconds.
#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch.hpp"
#include "cli_common.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex_tools;
namespace fs = std::filesystem;

namespace {

// printf into a growing string: the report is printed whole, in input order.
__attribute__((format(printf, 2, 3))) void add(std::string& out, const char* format, ...) {
    char line[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(line, sizeof line, format, args);
    va_end(args);
    out += line;
}

const char* kind_name(vqtex_map_kind kind) {
    return kind == VQTEX_MAP_NORMAL ? "normal" : kind == VQTEX_MAP_DATA ? "data" : "colour";
}

FileReport info_one(const std::string& input) {
    if (fs::is_directory(input)) throw std::runtime_error("folder '" + input + "' holds no .vqt file");
    const std::vector<uint8_t> bytes = load_bytes(input);
    vqtex_file_info info{};
    vqtex_error err{};
    if (vqtex_inspect(bytes.data(), bytes.size(), 0, &info, &err) != VQTEX_OK)
        throw std::runtime_error(input + ": " + err.detail);
    // Bytes per kind of section, all levels together.
    // Formats 3 to 8 hold an atlas and the engine's parameters instead;
    // formats 4 to 8 have no sections, and inspect lists their two parts
    // under the same tags (vqtex.h).
    // An atlas file is one whose atlas has a size (vqtex.h), so a new
    // format version needs no change here; only version 3 has sections.
    const bool atlas = info.atlas_width != 0;
    const bool compact = atlas && info.format_version != 3;
    const char* tree_kinds[] = {"LEVL", "HIST", "TOPO", "CODE", "ENTR"};
    const char* tree_meaning[] = {"level parameters", "noise histograms", "tree topology + leaf weights",
                                  "leaf codewords", "leaf entries (pixels + keys)"};
    const char* atlas_kinds[] = {"ATLS", "SYNP"};
    const char* atlas_meaning[] = {compact ? "AV1 bitstream (the atlas)" : "atlas (AV1 image)", "synthesis parameters"};
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
    FileReport r;
    auto& j = r.json;
    j["file"] = input;
    j["bytes"] = info.file_bytes;
    j["format_version"] = info.format_version;
    j["exemplar_width"] = info.exemplar_width;
    j["exemplar_height"] = info.exemplar_height;
    j["channels"] = info.channels;
    j["levels"] = info.levels;
    j["seam_closing"] = info.seam_closing;
    j["precision"] = info.precision;
    j["seed"] = info.seed;
    j["exemplar_frames"] = info.exemplar_frames;
    if (atlas) {
        j["atlas_width"] = info.atlas_width;
        j["atlas_height"] = info.atlas_height;
        j["atlas_x"] = info.atlas_x;
        j["atlas_y"] = info.atlas_y;
        j["coder"] = "AV1";  // the only atlas coder of formats 3 to 8
        j["blend"] = info.blend;
        j["relocate"] = info.relocate;
        j["edge_guard"] = info.edge_guard;
        j["cut"] = info.cut;
        j["cover"] = info.cover;
        j["atlas_wraps"] = info.atlas_wraps != 0;
        j["period_bar"] = info.period_bar != 0;
        j["quilt_block"] = info.quilt_block;
        if (info.atlas_frames) j["atlas_frames"] = info.atlas_frames;
        j["atlas_share"] = double(info.atlas_width) * info.atlas_height /
                           (double(info.exemplar_width) * info.exemplar_height);
    }
    j["codewords"] = nlohmann::ordered_json::array();
    for (uint32_t l = 0; l < info.levels; ++l) j["codewords"].push_back(info.codewords[l]);
    j["sections"] = nlohmann::ordered_json::array();
    for (uint32_t i = 0; i < info.section_count; ++i)
        j["sections"].push_back({{"tag", info.sections[i].tag},
                                 {"level", info.sections[i].level},
                                 {"kind", info.sections[i].kind},
                                 {"raw", info.sections[i].raw_bytes},
                                 {"stored", info.sections[i].stored_bytes}});
    j["header_and_checksum"] = overhead;
    // A plain colour texture is one map, "texture": the text shows maps
    // only for a set, a normal or data map stored alone, or a map of more
    // than 8 bits; the JSON lists every atlas file's, and says the bits a
    // sample of every file (trees and animations hold 8).
    const uint32_t map_count = std::min<uint32_t>(info.map_count, VQTEX_MAX_MAPS);
    uint32_t bits = 8;
    for (uint32_t i = 0; i < map_count; ++i) bits = std::max(bits, info.maps[i].bits);
    const bool show_maps = map_count > 1 || (map_count == 1 && (info.maps[0].kind != VQTEX_MAP_COLOUR || bits > 8));
    j["bits"] = bits;
    if (map_count > 0) {
        j["maps"] = nlohmann::ordered_json::array();
        for (uint32_t i = 0; i < map_count; ++i)
            j["maps"].push_back({{"name", info.maps[i].name},
                                 {"kind", kind_name(info.maps[i].kind)},
                                 {"channels", info.maps[i].channels},
                                 {"bits", info.maps[i].bits},
                                 {"bytes", info.maps[i].bytes},
                                 {"predicted_from", info.map_predicted_from[i] < 0
                                                        ? nlohmann::ordered_json(nullptr)
                                                        : nlohmann::ordered_json(info.maps[info.map_predicted_from[i]].name)}});
    }

    std::string& t = r.text;
    add(t, "%s: vqtex format %u, %llu bytes, checksum OK\n", input.c_str(), info.format_version,
        (unsigned long long)info.file_bytes);
    add(t, "example   %ux%u, %u channel%s; default seed %llu\n", info.exemplar_width, info.exemplar_height,
        info.channels, info.channels == 1 ? "" : "s", (unsigned long long)info.seed);
    if (info.atlas_frames) {
        add(t, "animation a loop of %u frames (the default output length)\n", info.atlas_frames);
    } else if (info.exemplar_frames) {
        add(t, "animation %u example frames; windows", info.exemplar_frames);
        for (uint32_t l = 0; l < info.levels; ++l)
            add(t, " {%ux%ux%u,%u}", info.shapes[l].rows, info.shapes[l].cols, info.window_frames[l],
                info.shapes[l].levels);
        add(t, " (finest first)\n");
    }
    if (atlas) {
        const std::string header =
            compact ? "; compact header (format " + std::to_string(info.format_version) + ")" : std::string();
        const bool whole = info.atlas_width == info.exemplar_width && info.atlas_height == info.exemplar_height;
        const double share = 100.0 * double(info.atlas_width) * info.atlas_height /
                             (double(info.exemplar_width) * info.exemplar_height);
        const std::string origin = info.atlas_x || info.atlas_y ? " at (" + std::to_string(info.atlas_x) + ", " +
                                                                     std::to_string(info.atlas_y) + ")"
                                                               : std::string();
        const std::string part = whole ? " (the whole example"
                                       : " (a part of the example" + origin + ", " +
                                             std::to_string(int(share + 0.5)) + "% of its area";
        const std::string frames = info.atlas_frames ? "x" + std::to_string(info.atlas_frames) : std::string();
        add(t, "atlas     %ux%u%s%s%s), coded as AV1%s%s\n", info.atlas_width, info.atlas_height, frames.c_str(),
            part.c_str(), info.atlas_wraps ? (info.period_bar ? ", wrapping, no repeat of it a period on" : ", wrapping") : "", info.atlas_frames ? " with inter frames" : "",
            header.c_str());
        const std::string seams =
            info.blend ? "seams blended over " + std::to_string(info.blend) + " pixels" : "seams not blended";
        // A wrapping atlas has no edge to guard, and its copies are not
        // relocated (FORMAT.md §4.9), whatever the parameters say.
        const std::string copies = info.atlas_wraps ? ", no relocation or edge guard (the atlas wraps)"
                                   : info.relocate  ? ", copies relocated (" + std::to_string(info.relocate) +
                                                         " positions tried each)"
                                                    : std::string();
        const std::string edges = info.edge_guard && !info.atlas_wraps
                                      ? ", edge guard " + std::to_string(info.edge_guard) + " pixels"
                                      : std::string();
        const std::string cuts =
            info.cut ? ", borders cut within " + std::to_string(info.cut) + " pixels" : std::string();
        const std::string covers =
            info.cover ? ", long borders covered within " + std::to_string(info.cover) + " pixels" : std::string();
        if (info.atlas_frames)
            add(t, "decoding  coherent engine for animations, %u levels, an atlas of %u voxels, %s in each frame%s\n",
                info.levels, info.codewords[0], seams.c_str(), cuts.c_str());
        else if (info.quilt_block)
            add(t, "decoding  image quilting, blocks of %ux%u pixels, an atlas of %u pixels, %s\n", info.quilt_block,
                info.quilt_block, info.codewords[0], seams.c_str());
        else
            add(t, "decoding  coherent engine, %u levels, an atlas of %u pixels, %s%s%s%s%s\n", info.levels,
                info.codewords[0], seams.c_str(), copies.c_str(), edges.c_str(), cuts.c_str(), covers.c_str());
    } else
        add(t, "decoding  %u levels, %s init, backtrack %u, seam closing %s, %u-bit codewords, %u-bit pixels\n",
            info.levels, info.init ? "noise" : "parent", info.backtrack, info.seam_closing ? "on" : "off",
            info.precision, info.pixel_precision);
    if (show_maps) {
        add(t, "maps      %u%s\n", map_count, map_count > 1 ? ", decoded aligned (one synthesis for all)" : "");
        int width = 0;
        for (uint32_t i = 0; i < map_count; ++i) width = std::max(width, int(std::strlen(info.maps[i].name)));
        for (uint32_t i = 0; i < map_count; ++i)
            add(t, "  %-*s  %-6s  %u channel%s  %2u bits  %7llu bytes of coded atlas%s%s\n", width, info.maps[i].name,
                kind_name(info.maps[i].kind), info.maps[i].channels, info.maps[i].channels == 1 ? " " : "s",
                info.maps[i].bits, (unsigned long long)info.maps[i].bytes,
                info.map_predicted_from[i] < 0 ? "" : ", predicted from ",
                info.map_predicted_from[i] < 0 ? "" : info.maps[info.map_predicted_from[i]].name);
    }
    for (uint32_t l = 0; l < info.levels && !atlas; ++l)
        add(t, "  level %u  {%ux%u,%u}  %5u codewords  %6u entries  %5u closing codewords\n", l, info.shapes[l].rows,
            info.shapes[l].cols, info.shapes[l].levels, info.codewords[l], info.entries[l],
            info.closing_codewords[l]);
    add(t, compact ? "bytes by part:\n" : "bytes by section kind (stored, with section headers):\n");
    for (int k = 0; k < kind_count; ++k)
        add(t, "  %s  %-32s %8llu  %5.1f%%\n", kinds[k], meaning[k], (unsigned long long)per_kind[k],
            100.0 * double(per_kind[k]) / double(info.file_bytes));
    add(t, "  ----  %-32s %8llu  %5.1f%%\n", "file header and checksum", (unsigned long long)overhead,
        100.0 * double(overhead) / double(info.file_bytes));
    if (!compact) add(t, "sections:\n");
    for (uint32_t i = 0; i < info.section_count && !compact; ++i)
        add(t, "  %s level %u %-8s raw %8llu  stored %8llu\n", info.sections[i].tag, info.sections[i].level,
            info.sections[i].kind == 2 ? "seam" : info.sections[i].kind ? "closing" : "",
            (unsigned long long)info.sections[i].raw_bytes, (unsigned long long)info.sections[i].stored_bytes);
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-info: verify .vqt files and print their contents and byte breakdown.\n"
                 "Batch: vqtex-info textures/ more.vqt --json   (one JSON line per file)"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    uint32_t threads = 0;
    bool json = false;
    app.add_option("files", files, ".vqt files, or folders of them")->required();
    app.add_flag("--json", json, "machine-readable output, one JSON line per file");
    app.add_option("-j,--threads", threads, "files checked at once (default: all cores)");
    CLI11_PARSE(app, argc, argv);
    const std::vector<std::string> inputs = expand_inputs(files, {".vqt"});
    BatchOptions options;
    options.program = "vqtex-info";
    options.jobs = threads;
    options.json = json;
    options.names = &inputs;
    options.name_key = "file";
    options.progress = inputs.size() > 1;
    return run_batch(inputs.size(), options, [&](std::size_t i, unsigned) { return info_one(inputs[i]); });
}
