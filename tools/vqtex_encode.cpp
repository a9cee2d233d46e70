// vqtex-encode - encode an example texture into a compact .vqt file holding
// its codebook only (paper section 6): an AV1 atlas by default, TSVQ trees
// with --trees; through the public API only. One
// example (`vqtex-encode IN OUT.vqt`), a batch (`vqtex-encode IN... -o DIR`)
// or a material set (`vqtex-encode --map albedo=A.png --map normal=N.png OUT.vqt`).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch.hpp"
#include "cli_common.hpp"
#include "image_io.hpp"
#include "sequence_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;
namespace fs = std::filesystem;

namespace {

// A still atlas's size and place in the report: in the JSON always, in the
// text when it is not the whole example.
void add_atlas_json(const vqtex_encode_stats& stats, FileReport& r) {
    static const char* const kAtlasKinds[] = {"whole", "part", "tile"};
    if (stats.atlas_width)
        r.json["atlas"] = {{"width", stats.atlas_width},
                           {"height", stats.atlas_height},
                           {"x", stats.atlas_x},
                           {"y", stats.atlas_y},
                           {"kind", kAtlasKinds[std::min(stats.atlas_kind, 2u)]},
                           {"wraps", stats.atlas_wraps != 0},
                           {"period_bar", stats.period_bar != 0},
                           {"quilt", stats.quilt != 0},
                           {"example_tiles", stats.example_tiles != 0}};
}

void add_atlas_text(const vqtex_encode_stats& stats, FileReport& r) {
    if (stats.quilt)
        r.text += "atlas: the whole example, which tiles: the output is laid out by quilting\n";
    else if (stats.atlas_width && stats.atlas_kind == 0 && stats.atlas_wraps)
        r.text += stats.period_bar ? "atlas: the whole example, which tiles: it wraps, and no copy repeats it a period on\n"
                                   : "atlas: the whole example, which repeats its tile: it wraps\n";
    else if (stats.atlas_width && stats.atlas_kind == 0 && stats.example_tiles)
        r.text += "note: the example tiles but repeats a small tile; --tileable-example lets copies run across "
                  "its edges (docs/ATLAS.md)\n";
    if (!stats.atlas_width || stats.atlas_kind == 0) return;
    char line[256];
    std::snprintf(line, sizeof line, "atlas %ux%u: %s\n", stats.atlas_width, stats.atlas_height,
                  stats.atlas_kind == 2 ? "the tile the example repeats"
                                        : ("the part at (" + std::to_string(stats.atlas_x) + ", " +
                                           std::to_string(stats.atlas_y) + ")").c_str());
    r.text += line;
}

// The animated-texture path (paper section 5.2): a frame sequence in, a
// .vqt file out.
FileReport encode_animation(const std::string& input, const std::string& output, vqtex_volume_encode_params p,
                            bool quiet, ProgressBar* bar) {
    LoadedSequence seq = load_sequence(input);
    if (!seq.notice.empty() && !quiet) write_stderr("vqtex-encode: note: " + input + ": " + seq.notice + "\n");
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    const vqtex_volume v{seq.width, seq.height, seq.frames, seq.channels, seq.pixels.data()};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode_volume(&p, &v, &data, &size, &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    FileReport r;
    char line[2048];
    r.json = {{"input", input},       {"output", output},         {"width", seq.width}, {"height", seq.height},
              {"frames", seq.frames}, {"channels", seq.channels}, {"bits", 8},          {"bytes", size},
              {"encode_seconds", seconds}};
    if (p.codebook == VQTEX_CODEBOOK_ATLAS)
        r.json["atlas"] = {{"width", stats.atlas_width}, {"height", stats.atlas_height}, {"x", stats.atlas_x},
                           {"y", stats.atlas_y},         {"frames", stats.atlas_frames},
                           {"first_frame", stats.atlas_first_frame},
                           {"kind", stats.atlas_kind ? "part" : "whole"}};
    if (!seq.notice.empty()) r.json["notices"] = std::vector<std::string>{input + ": " + seq.notice};
    std::snprintf(line, sizeof line, "%s (%ux%u, %u frames, %u channels) -> %s\n", input.c_str(), seq.width,
                  seq.height, seq.frames, seq.channels, output.c_str());
    r.text = line;
    if (p.codebook == VQTEX_CODEBOOK_ATLAS) {
        std::snprintf(line, sizeof line, "atlas: %ux%u at (%u, %u), frames %u to %u of the example\n",
                      stats.atlas_width, stats.atlas_height, stats.atlas_x, stats.atlas_y, stats.atlas_first_frame,
                      stats.atlas_first_frame + stats.atlas_frames - 1);
        r.text += line;
    }
    std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, %.3f s\n", size,
                  8.0 * double(size) / (double(seq.width) * seq.height * seq.frames), seconds);
    r.text += line;
    return r;
}

// One map of a material set, as --map or --normal gives it.
struct MapInput {
    std::string name;
    vqtex_map_kind kind = VQTEX_MAP_DATA;
    bool kind_given = false;  // else implied by the name
    uint32_t weight = 0;
    std::string file;
};

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

const char* kind_name(vqtex_map_kind kind) {
    return kind == VQTEX_MAP_NORMAL ? "normal" : kind == VQTEX_MAP_DATA ? "data" : "colour";
}

// The kind a map's name implies when --map gives none: the usual names of
// colour and normal maps; any other map holds values as they are.
vqtex_map_kind kind_from_name(const std::string& name) {
    const std::string n = lower(name);
    if (n.rfind("normal", 0) == 0 || n.rfind("nrm", 0) == 0) return VQTEX_MAP_NORMAL;
    for (const char* colour : {"albedo", "diffuse", "basecolor", "base_color", "color", "colour", "emissive"})
        if (n == colour) return VQTEX_MAP_COLOUR;
    return VQTEX_MAP_DATA;
}

// "NAME[:KIND[:WEIGHT]]=FILE". Throws a one-line reason quoting `spec`.
MapInput parse_map(const std::string& spec) {
    const std::string where = "--map '" + spec + "'";
    const std::size_t eq = spec.find('=');
    if (eq == std::string::npos || eq + 1 == spec.size())
        throw std::invalid_argument(where + " is not NAME[:KIND[:WEIGHT]]=FILE (e.g. --map albedo=stone_albedo.png)");
    MapInput m;
    m.file = spec.substr(eq + 1);
    std::vector<std::string> parts{""};
    for (const char c : spec.substr(0, eq)) {
        if (c == ':')
            parts.emplace_back();
        else
            parts.back() += c;
    }
    if (parts.size() > 3)
        throw std::invalid_argument(where +
                                    ": give at most a kind and a weight after the name (NAME:KIND:WEIGHT=FILE)");
    m.name = parts[0];
    // The name becomes part of file names ({map} in vqtex-decode's output).
    const bool name_ok =
        !m.name.empty() && m.name.size() <= VQTEX_MAX_MAP_NAME && std::all_of(m.name.begin(), m.name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
        });
    if (!name_ok)
        throw std::invalid_argument(where + ": the name '" + m.name + "' must be 1 to " +
                                    std::to_string(VQTEX_MAX_MAP_NAME) + " characters of A-Z a-z 0-9 _ . -");
    if (parts.size() >= 2) {
        const std::string kind = lower(parts[1]);
        if (kind == "colour" || kind == "color")
            m.kind = VQTEX_MAP_COLOUR;
        else if (kind == "normal")
            m.kind = VQTEX_MAP_NORMAL;
        else if (kind == "data")
            m.kind = VQTEX_MAP_DATA;
        else
            throw std::invalid_argument(where + ": kind '" + parts[1] + "' is not colour, normal or data");
        m.kind_given = true;
    } else {
        m.kind = kind_from_name(m.name);
    }
    if (parts.size() == 3) {
        const std::string& w = parts[2];
        if (w.size() != 1 || w[0] < '0' || w[0] > '8')
            throw std::invalid_argument(where + ": weight '" + w + "' is not 0 to 8 (0: the kind's default)");
        m.weight = uint32_t(w[0] - '0');
    }
    return m;
}

// The maps of all --map options: at most VQTEX_MAX_MAPS, names distinct
// even in case (they name files, and some file systems ignore case).
std::vector<MapInput> parse_maps(const std::vector<std::string>& specs) {
    if (specs.size() > VQTEX_MAX_MAPS)
        throw std::invalid_argument(std::to_string(specs.size()) + " --map options: a set holds at most " +
                                    std::to_string(VQTEX_MAX_MAPS) + " maps; encode the others into another file");
    std::vector<MapInput> maps;
    for (const std::string& spec : specs) {
        MapInput m = parse_map(spec);
        for (const MapInput& earlier : maps) {
            if (earlier.name == m.name)
                throw std::invalid_argument("--map: two maps are named '" + m.name +
                                            "': give each map a name of its own");
            if (lower(earlier.name) == lower(m.name))
                throw std::invalid_argument("--map: the names '" + earlier.name + "' and '" + m.name +
                                            "' differ only in case, and they name the decoded files: give each "
                                            "map a name of its own");
        }
        maps.push_back(std::move(m));
    }
    return maps;
}

// What the options set, for every file.
struct Settings {
    vqtex_encode_params params;  // without threads and progress
    std::string shapes;
    bool normal = false;       // --normal: each example is a normal map
    bool data = false;         // --data: each example holds values (height, roughness, a mask)
    bool quiet = false;
};

// How a map's samples are read: colour by the sRGB curve, normal and data
// maps as values; more than 8 bits a sample kept as 16 (the file keeps 12).
ReadOptions read_options_for(vqtex_map_kind kind) {
    ReadOptions o;
    o.space = kind == VQTEX_MAP_COLOUR ? SampleSpace::colour : SampleSpace::data;
    o.keep_16 = true;
    return o;
}

// What the reader converted, said on stderr (unless quiet) and kept for
// the JSON report: a note that only reaches a terminal is lost to a
// pipeline.
void note(const Settings& s, const std::string& file, const LoadedImage& img, std::vector<std::string>& notices) {
    if (img.notice.empty()) return;
    notices.push_back(file + ": " + img.notice);
    if (!s.quiet) write_stderr("vqtex-encode: note: " + notices.back() + "\n");
}

// The maps' files, loaded and checked before the library sees them, so
// that an error names the map and its file. `single`: the one map is the
// EXAMPLE of --normal or --data (the messages say so).
std::vector<LoadedImage> load_maps(const Settings& s, const std::vector<MapInput>& maps, bool single,
                                   std::vector<std::string>& notices) {
    std::vector<LoadedImage> images;
    images.reserve(maps.size());
    for (const MapInput& m : maps) {
        const std::string what = single ? "'" + m.file + "'" : "map '" + m.name + "' ('" + m.file + "')";
        images.push_back(load_image(m.file, read_options_for(m.kind)));
        const LoadedImage& img = images.back();
        note(s, m.file, img, notices);
        if (m.kind == VQTEX_MAP_NORMAL && img.channels != 3) {
            const std::string has =
                what + " has " + std::to_string(img.channels) + (img.channels == 1 ? " channel" : " channels");
            const std::string drop_alpha = img.channels == 4 ? "remove its alpha channel, or " : "";
            if (single)
                throw std::invalid_argument(has + ": --normal takes a normal map of 3 (x, y, z): " + drop_alpha +
                                            "encode it without --normal");
            throw std::invalid_argument(
                has + (m.kind_given ? ", but a normal map" : ", but its name makes it a normal map, which") +
                " has 3 (x, y, z): " + drop_alpha + "give it another kind, e.g. --map " + m.name + ":data=" + m.file);
        }
        const LoadedImage& first = images.front();
        if (img.width != first.width || img.height != first.height)
            throw std::invalid_argument(what + " is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                                        " but map '" + maps[0].name + "' ('" + maps[0].file + "') is " +
                                        std::to_string(first.width) + "x" + std::to_string(first.height) +
                                        ": the maps of a set have one size; resize them to it");
    }
    return images;
}

// The bits a sample each map keeps in `file`, as the file itself says; a
// file too large for inspect's default memory limit gets what vqtex.h
// promises instead (12 bits of 16-bit samples).
std::vector<uint32_t> bits_in_file(const vqtex_cpp::Buffer& file, const std::vector<LoadedImage>& images) {
    vqtex_file_info info{};
    const bool inspected = vqtex_inspect(file.data(), file.size(), 0, &info, nullptr) == VQTEX_OK &&
                           info.map_count == images.size();
    std::vector<uint32_t> bits;
    for (std::size_t i = 0; i < images.size(); ++i)
        bits.push_back(inspected ? info.maps[i].bits : images[i].bits == 16 ? 12u : 8u);
    return bits;
}

// A set's maps, loaded, into `output`. `single`: the set is one EXAMPLE
// (--normal, --data, or an image of more than 8 bits a sample), reported
// as one input.
FileReport encode_loaded_set(const Settings& s, const std::vector<MapInput>& maps,
                             const std::vector<LoadedImage>& images, std::vector<std::string> notices,
                             const std::string& output, unsigned threads, ProgressBar* bar, bool single) {
    vqtex_encode_params p = s.params;
    p.threads = threads;
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    // 16-bit samples go as image16, which the file keeps 12 bits of.
    std::vector<vqtex_image16> deep(maps.size());
    std::vector<vqtex_map> set(maps.size());
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const LoadedImage& img = images[i];
        set[i].name = maps[i].name.c_str();
        set[i].kind = maps[i].kind;
        set[i].weight = maps[i].weight;
        if (img.bits == 16) {
            // The library reads the samples only.
            deep[i] = vqtex_image16{img.width, img.height, img.channels, const_cast<uint16_t*>(img.pixels16.data())};
            set[i].image16 = &deep[i];
        } else {
            set[i].image = vqtex_image{img.width, img.height, img.channels, const_cast<uint8_t*>(img.pixels.data())};
        }
    }
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode_maps(&p, set.data(), uint32_t(set.size()), &data, &size, &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    const std::vector<uint32_t> bits = bits_in_file(file, images);
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    const uint32_t width = images[0].width, height = images[0].height;
    const double pixels = double(width) * height;
    // An atlas found for a target size comes from no preset: no quality to report.
    const bool preset_free = p.target_size != 0;
    const int quality = int(stats.quality);
    std::vector<std::string> names, kinds, files;
    std::vector<uint32_t> channels;
    for (std::size_t i = 0; i < maps.size(); ++i) {
        names.push_back(maps[i].name);
        kinds.push_back(kind_name(maps[i].kind));
        files.push_back(maps[i].file);
        channels.push_back(images[i].channels);
    }
    FileReport r;
    auto& j = r.json;
    if (single)
        j["input"] = files[0];
    else
        j["inputs"] = files;
    j["output"] = output;
    j["width"] = width;
    j["height"] = height;
    j["maps"] = names;
    j["kinds"] = kinds;
    j["channels"] = channels;
    j["bits"] = bits;  // a sample in the file, per map: 12 for 16-bit inputs
    j["bytes"] = size;
    j["bpp"] = 8.0 * double(size) / pixels;
    j["quality"] = preset_free ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(quality);
    j["attempts"] = stats.attempts;
    j["encode_seconds"] = seconds;
    add_atlas_json(stats, r);
    if (!notices.empty()) j["notices"] = notices;
    char line[2048];
    if (single) {
        const std::string what =
            maps[0].kind == VQTEX_MAP_COLOUR ? std::to_string(channels[0]) + " channels" : kinds[0] + " map";
        std::snprintf(line, sizeof line, "%s (%ux%u, %s, %u bits kept) -> %s\n", files[0].c_str(), width, height,
                      what.c_str(), bits[0], output.c_str());
        r.text = line;
    } else {
        std::snprintf(line, sizeof line, "%zu maps of %ux%u -> %s\n", maps.size(), width, height, output.c_str());
        r.text = line;
        std::size_t name_width = 0;
        for (const std::string& name : names) name_width = std::max(name_width, name.size());
        for (std::size_t i = 0; i < maps.size(); ++i) {
            std::snprintf(line, sizeof line, "  %-*s  %-6s  %u channel%s  %2u bits  %s\n", int(name_width),
                          names[i].c_str(), kinds[i].c_str(), channels[i], channels[i] == 1 ? " " : "s",
                          bits[i], files[i].c_str());
            r.text += line;
        }
    }
    if (preset_free)
        std::snprintf(line, sizeof line,
                      "%zu bytes, %.3f bits per example pixel, atlas chosen for the target size, %.3f s\n", size,
                      8.0 * double(size) / pixels, seconds);
    else
        std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, quality %d, %.3f s\n", size,
                      8.0 * double(size) / pixels, quality, seconds);
    r.text += line;
    add_atlas_text(stats, r);
    return r;
}

// A set's maps into `output` (see load_maps and encode_loaded_set).
FileReport encode_set(const Settings& s, const std::vector<MapInput>& maps, const std::string& output, unsigned threads,
                      ProgressBar* bar, bool single) {
    std::vector<std::string> notices;
    const std::vector<LoadedImage> images = load_maps(s, maps, single, notices);
    return encode_loaded_set(s, maps, images, std::move(notices), output, threads, bar, single);
}

// Encodes `input` into `output` with `threads` library threads; `bar` draws
// a single file's progress (null in a batch). Throws a one-line message.
FileReport encode_one(const Settings& s, const std::string& input, const std::string& output, unsigned threads,
                      ProgressBar* bar) {
    if (s.normal || s.data) {
        const char* option = s.normal ? "--normal" : "--data";
        if (is_sequence(input))
            throw std::invalid_argument(std::string(option) + " takes a still image: '" + input + "' is an animation");
        MapInput m;
        m.name = s.normal ? "normal" : "data";
        m.kind = s.normal ? VQTEX_MAP_NORMAL : VQTEX_MAP_DATA;
        m.kind_given = true;
        m.file = input;
        return encode_set(s, {m}, output, threads, bar, true);
    }
    vqtex_encode_params p = s.params;
    p.threads = threads;
    if (is_sequence(input)) {
        // A space-time atlas unless trees are asked for; the trees take
        // the still texture's preset and options, trained as the
        // animation defaults say.
        vqtex_volume_encode_params vp;
        vqtex_volume_encode_params_init(&vp);
        vp.codebook = p.codebook;
        vp.quality = p.quality;
        vp.target_size = p.target_size;
        if (p.target_size && p.codebook == VQTEX_CODEBOOK_TREES)
            throw std::invalid_argument("--target-size takes an animation's atlas: drop --trees and the options "
                                        "that describe trees");
        vp.levels = p.levels;
        vp.example_tileable = p.example_tileable == VQTEX_TILEABLE_YES ? 1u : 0u;
        vp.seed = p.seed;
        vp.threads = p.threads;
        const float train_fraction = vp.tsvq.train_fraction;
        vp.tsvq = p.trees.tsvq;
        vp.tsvq.train_fraction = train_fraction;
        vp.precision = p.trees.precision;
        vp.pixel_precision = p.trees.pixel_precision;
        vp.smoothing = p.trees.smoothing;
        vp.backtrack = p.trees.backtrack;
        vp.init = p.trees.init;
        if (!s.shapes.empty()) parse_shapes3(s.shapes, vp.shapes);
        return encode_animation(input, output, vp, s.quiet, bar);
    }
    if (!s.shapes.empty()) parse_shapes(s.shapes, p.trees.shapes);
    // An image of more than 8 bits a sample keeps 12 in an atlas: a set of
    // one colour map, "texture" (what a file that is not a set decodes
    // as). Trees hold 8 bits, and the reader's note says so.
    ReadOptions read;
    read.keep_16 = p.codebook == VQTEX_CODEBOOK_ATLAS;
    std::vector<std::string> notices;
    std::vector<LoadedImage> loaded;
    loaded.push_back(load_image(input, read));
    note(s, input, loaded[0], notices);
    if (loaded[0].bits == 16) {
        MapInput m;
        m.name = "texture";
        m.kind = VQTEX_MAP_COLOUR;
        m.kind_given = true;
        m.file = input;
        return encode_loaded_set(s, {m}, loaded, std::move(notices), output, threads, bar, true);
    }
    const LoadedImage& example = loaded[0];
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    const vqtex_image img{example.width, example.height, example.channels, const_cast<uint8_t*>(example.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode(&p, &img, &data, &size, &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    const double pixels = double(example.width) * example.height;
    // An atlas found for a target size comes from no preset: no quality to report.
    const bool preset_free = p.target_size && p.codebook == VQTEX_CODEBOOK_ATLAS;
    const int quality = int(stats.quality);
    FileReport r;
    char line[2048];
    r.json = {{"input", input},
              {"output", output},
              {"width", example.width},
              {"height", example.height},
              {"channels", example.channels},
              {"bits", 8},
              {"bytes", size},
              {"bpp", 8.0 * double(size) / pixels},
              {"quality", preset_free ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(quality)},
              {"attempts", stats.attempts},
              {"encode_seconds", seconds},
              {"codewords", std::vector<uint32_t>(stats.codewords, stats.codewords + stats.levels)},
              {"entries", std::vector<uint32_t>(stats.entries, stats.entries + stats.levels)}};
    add_atlas_json(stats, r);
    if (!notices.empty()) r.json["notices"] = notices;
    std::snprintf(line, sizeof line, "%s (%ux%u, %u channels) -> %s\n", input.c_str(), example.width,
                  example.height, example.channels, output.c_str());
    r.text = line;
    if (preset_free)
        std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, atlas chosen for the target size, %.3f s\n",
                      size, 8.0 * double(size) / pixels, seconds);
    else
        std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, quality %d%s, %.3f s\n", size,
                      8.0 * double(size) / pixels, quality, p.target_size ? " (target-size search)" : "", seconds);
    r.text += line;
    add_atlas_text(stats, r);
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-encode: encode an example texture into a .vqt codebook file.\n"
                 "Example: vqtex-encode corpus/cellular_128.png cellular.vqt --quality 60"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string out_dir, suffix, codewords, shapes;
    int quality = VQTEX_QUALITY_DEFAULT;
    uint32_t precision = 0, pixel_precision = 0, entries = 0, levels = 0, backtrack = 0, threads = 0;
    uint32_t smoothing = 0, closing_divisor = 0, closing_window = 0;
    bool no_entry_keys = false;
    uint64_t target_size = 0, seed = 1;
    bool json = false, quiet = false, no_closing = false, tileable = false, not_tileable = false, atlas = false,
         trees = false;
    bool animation = false, normal = false, data = false;
    std::vector<std::string> map_specs;
    app.add_option("files", files,
                   "EXAMPLE OUTPUT.vqt: an image (any format OpenImageIO reads) or an animation (a numbered "
                   "sequence 'frames/frame_%03d.png', a folder of frames, or a multi-image file); with -o: "
                   "examples and folders of images, one texture each; with --map: OUTPUT.vqt only")
        ->required();
    // One value per --map: the positional OUTPUT may follow the last one.
    app.add_option("--map", map_specs,
                   "NAME[:KIND[:WEIGHT]]=FILE, repeatable (up to 16): a material set, its maps (one size) "
                   "decoded aligned. KIND colour|normal|data (default from the name: normal*/nrm* normal; albedo, "
                   "diffuse, basecolor, base_color, color, colour, emissive colour; else data); WEIGHT 0 to 8, "
                   "its say in the synthesis (0: the kind's default)")
        ->allow_extra_args(false);
    app.add_flag("--normal", normal,
                 "EXAMPLE is a tangent-space normal map (3 channels): stored as a set of one map named 'normal'");
    app.add_flag("--data", data,
                 "EXAMPLE holds values, not colour (height, roughness, a mask): stored as a set of one data map "
                 "named 'data'; a float file's values are read as they are, not as linear light");
    auto* out_dir_opt = app.add_option("-o,--output-dir", out_dir,
                                       "batch: write OUTDIR/NAME[SUFFIX].vqt for every example (created if missing)");
    app.add_option("--suffix", suffix, "batch: text added to each output's name");
    app.add_flag("--animation", animation,
                 "EXAMPLE is an animation: needed for a folder, whose images are then its frames in name order "
                 "(without -o)")
        ->excludes(out_dir_opt);
    app.add_option("-q,--quality", quality,
                   "preset from 0 (smallest file) to 100 (best texture); an atlas's byte budget: 1 KB per "
                   "128x128 pixels at 0, doubling every 25 points (4 KB at 50, 16 KB at 100)")
        ->check(CLI::Range(0, 100))->capture_default_str();
    app.add_option("--target-size", target_size, "largest file in bytes: the best atlas (or trees preset) that fits");
    auto* atlas_flag = app.add_flag("--atlas", atlas,
                                    "store the example as an AV1 atlas decoded by the coherent engine (format v7, "
                                    "the default for still textures; uses --quality or --target-size, --seed, "
                                    "--levels, --tileable-example)");
    app.add_flag("--trees", trees,
                 "store the paper's TSVQ codebooks instead (format v1, decoded by the paper's engine; "
                 "the options below that name TSVQ, codewords, entries or precision apply to it)")
        ->excludes(atlas_flag);
    app.add_option("-k,--codewords", codewords, "TSVQ leaves: K for every level or K0,K1,.. finest first");
    app.add_option("--entries", entries, "outputs per leaf, 1 to 64")->check(CLI::Range(1, 64));
    app.add_option("-p,--precision", precision, "bits per codeword sample, 1 to 8")->check(CLI::Range(1, 8));
    app.add_option("--pixel-precision", pixel_precision, "bits per output pixel sample, 1 to 8")
        ->check(CLI::Range(1, 8));
    app.add_option("--smoothing", smoothing, "average codeword taps away from the pixel in NxN blocks (1 = off)")
        ->check(CLI::Range(1, 8));
    app.add_flag("--no-entry-keys", no_entry_keys, "entries without keys, chosen at random (smaller)");
    app.add_option("--closing-divisor", closing_divisor, "seam-closing trees get 1/N of the leaves")
        ->check(CLI::Range(1, 1024));
    app.add_option("--closing-window", closing_window, "seam-closing window size (odd, 3 to 63)")
        ->check(CLI::Range(3, 63));
    app.add_option("--levels", levels, "pyramid levels (default: automatic)");
    app.add_option("--shapes", shapes, "neighbourhood per level, finest first, RxC:k (animations: RxCxD:k)");
    app.add_option("-L,--backtrack", backtrack, "TSVQ leaves the decoder visits per pixel (1 to 255)")
        ->check(CLI::Range(1, 255));
    app.add_option("--seed", seed, "default decoding seed stored in the file")->capture_default_str();
    app.add_flag("--no-seam-closing", no_closing, "omit the seam-closing trees (smaller, visible seam)");
    auto* tileable_flag = app.add_flag("--tileable-example", tileable,
                                       "the example tiles: use wrap-around neighbourhoods (an atlas of a still "
                                       "image or a set wraps without it when the example is found to tile)");
    app.add_flag("--no-tileable-example", not_tileable, "the example does not wrap, even if it is found to tile")
        ->excludes(tileable_flag);
    std::string layout = "auto";
    app.add_option("--layout", layout,
                   "how a wrapping atlas's output is laid out: auto (the better of the two on this example), "
                   "coherent (the engine) or quilt (image quilting)")
        ->check(CLI::IsMember({"auto", "coherent", "quilt"}))
        ->capture_default_str();
    app.add_option("-j,--threads", threads,
                   "threads (default: all cores), shared between the files of a batch; output is identical");
    app.add_flag("--json", json, "print machine-readable statistics on stdout (one JSON line per file)");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    CLI11_PARSE(app, argc, argv);

    try {
        vqtex_encode_params p;
        vqtex_encode_params_init(&p);
        p.quality = uint32_t(quality);
        vqtex_encode_params_preset(&p, quality);
        vqtex_trees_params& t = p.trees;
        if (!codewords.empty()) {
            if (codewords.find('.') != std::string::npos)
                throw std::invalid_argument("--codewords takes counts for the codec (e.g. 512 or 512,256)");
            parse_codewords(codewords, t.tsvq);
        }
        if (entries) t.tsvq.entries_per_leaf = entries;
        if (precision) t.precision = precision;
        if (pixel_precision) t.pixel_precision = pixel_precision;
        p.levels = levels;
        if (smoothing) t.smoothing = smoothing;
        if (no_entry_keys) t.tsvq.no_entry_keys = 1;
        if (closing_divisor) t.tsvq.closing_divisor = closing_divisor;
        if (closing_window) {
            if (closing_window % 2 == 0) throw std::invalid_argument("--closing-window must be odd");
            t.tsvq.closing_window = closing_window;
        }
        if (backtrack) t.backtrack = backtrack;
        if (no_closing) t.tsvq.seam_closing = 0;
        p.example_tileable = tileable       ? VQTEX_TILEABLE_YES
                             : not_tileable ? VQTEX_TILEABLE_NO
                                            : VQTEX_TILEABLE_DETECT;
        p.seed = seed;
        p.target_size = target_size;
        p.layout = layout == "quilt" ? VQTEX_LAYOUT_QUILT : layout == "coherent" ? VQTEX_LAYOUT_COHERENT : VQTEX_LAYOUT_AUTO;
        // Options that only a trees file has make no sense for an atlas.
        const bool tree_options = !codewords.empty() || entries || precision || pixel_precision || smoothing ||
                                  no_entry_keys || closing_divisor || closing_window || backtrack || no_closing ||
                                  !shapes.empty();
        if (atlas && tree_options)
            throw std::invalid_argument("codewords, entries, precision, smoothing, closing, backtrack and shapes "
                                        "describe TSVQ trees: add --trees, or drop them for an atlas");
        p.codebook = trees || tree_options ? VQTEX_CODEBOOK_TREES : VQTEX_CODEBOOK_ATLAS;
        Settings s;
        s.params = p;
        s.shapes = shapes;
        s.normal = normal;
        s.data = data;
        s.quiet = quiet;

        if (normal && data)
            throw std::invalid_argument("--normal and --data say two kinds for one EXAMPLE: give one");
        if (!map_specs.empty() && normal)
            throw std::invalid_argument(
                "--normal is for one image: in a set, give the normal map as --map normal=FILE");
        if (!map_specs.empty() && data)
            throw std::invalid_argument(
                "--data is for one image: in a set, give the data map as --map NAME:data=FILE");
        // A material set is stored as an atlas; the trees have no maps.
        if (!map_specs.empty() || normal || data) {
            const std::string set_option = normal ? "--normal" : data ? "--data" : "--map";
            if (trees) throw std::invalid_argument(set_option + " stores an atlas: drop --trees");
            if (tree_options)
                throw std::invalid_argument(set_option +
                                            " stores no TSVQ trees: drop the options that describe "
                                            "them (codewords, entries, precision, smoothing, closing, backtrack, "
                                            "shapes)");
        }
        if (!map_specs.empty()) {
            if (*out_dir_opt)
                throw std::invalid_argument("--map makes one file: give its OUTPUT.vqt instead of -o DIR");
            if (animation) throw std::invalid_argument("--map takes still images: drop --animation");
            if (files.size() > 1) {
                std::string extra;
                for (std::size_t i = 0; i + 1 < files.size(); ++i) extra += (i ? ", '" : "'") + files[i] + "'";
                throw std::invalid_argument("with --map, the one file argument is the OUTPUT.vqt: give " + extra +
                                            " as --map NAME=FILE, or drop it");
            }
            const std::vector<MapInput> maps = parse_maps(map_specs);
            const std::string& output = files[0];
            // A forgotten output would make an image the output, replacing it.
            const std::string ext = lower(fs::path(output).extension().string());
            const auto& images = image_extensions();
            if (std::find(images.begin(), images.end(), ext) != images.end())
                throw std::invalid_argument("with --map, the one file argument is the OUTPUT.vqt: '" + output +
                                            "' looks like an image; give the maps as --map NAME=FILE and the "
                                            "output last");
            for (const MapInput& m : maps) {
                std::error_code ec;
                if (fs::exists(output, ec) && fs::equivalent(m.file, output, ec))
                    throw std::invalid_argument("'" + output + "' is the file of map '" + m.name +
                                                "': give another OUTPUT.vqt, or the map would be replaced");
            }
            ProgressBar bar(!quiet && !json);
            const FileReport r = encode_set(s, maps, output, threads, &bar, false);
            print_report(r, json, quiet);
            return 0;
        }

        if (!*out_dir_opt) {
            require_single_pair(files, "OUTPUT .vqt", "encode", "examples");
            check_animation_request(files[0], animation, "encode");
            ProgressBar bar(!quiet && !json);
            const FileReport r = encode_one(s, files[0], files[1], threads, &bar);
            print_report(r, json, quiet);
            return 0;
        }

        // Batch: a folder means its images, each a texture of its own (an
        // animation in a batch is given as a numbered pattern).
        prepare_output_folder(out_dir);
        const std::vector<std::string> inputs = expand_inputs(files, image_extensions());
        BatchOutputs outputs(inputs);
        for (const std::string& in : inputs) {
            // A pattern's stem holds the %d field: name the texture after the folder part before it.
            outputs.add(batch_output_name(is_frame_pattern(in) ? fs::path(in).parent_path().string() : in, out_dir,
                                          suffix, "vqt"));
        }
        return run_batch(inputs.size(), batch_options("vqtex-encode", threads, json, quiet, inputs),
                         [&](std::size_t i, unsigned per_file) {
            outputs.check_first(i, "encode");
            check_batch_pair(inputs[i], outputs[i], "image file (an animation in a batch is a pattern: 'DIR/frame_%03d.png')");
            try {
                return encode_one(s, inputs[i], outputs[i], per_file, nullptr);
            } catch (const std::exception& e) {
                // The library's reasons do not name the file; a batch must.
                const std::string why = e.what();
                if (why.find(inputs[i]) != std::string::npos) throw;
                throw std::runtime_error(inputs[i] + ": " + why);
            }
        });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-encode: error: %s\n", e.what());
        return 1;
    }
}
