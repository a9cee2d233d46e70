// vqtex-decode - regenerate a texture of any size from a .vqt file by
// synthesis (paper section 6), through the public API only. One file
// (`vqtex-decode IN OUT`) or a batch (`vqtex-decode IN... -o DIR`); a
// material set's maps to one file each (`vqtex-decode IN 'out_{map}.png'`).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch.hpp"
#include "cli_common.hpp"
#include "image_io.hpp"
#include "sequence_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;

namespace {

namespace fs = std::filesystem;

struct Settings {
    vqtex_decode_params params;  // without threads and progress
    uint32_t frames = 0;
    bool mips = false;
    bool batch = false;  // -o DIR: outputs are named by --suffix
    std::string coords;  // --coords FILE, or empty
    bool quiet = false;
};

// The field of an output name that each map of a set replaces with its name.
constexpr std::string_view kMapField = "{map}";

bool has_map_field(const std::string& output) { return output.find(kMapField) != std::string::npos; }

std::string map_output_name(std::string pattern, const std::string& map) {
    for (std::size_t at; (at = pattern.find(kMapField)) != std::string::npos;)
        pattern.replace(at, kMapField.size(), map);
    return pattern;
}

// How to ask for one file per map, in the words of the call's mode.
std::string map_field_hint(const Settings& s) {
    return s.batch ? "put {map} in --suffix (e.g. --suffix '_{map}')"
                   : "put {map} in the output name (e.g. 'out_{map}.png')";
}

// How a map's samples go into an image file: colour on the sRGB curve
// (linear light in OpenEXR), normal and data maps as the values they are.
SampleSpace space_of(vqtex_map_kind kind) { return kind == VQTEX_MAP_COLOUR ? SampleSpace::colour : SampleSpace::data; }

// Writes one map as the library returned it: 8-bit samples, or a 12-bit
// map's widened to 16 bits (a 16-bit PNG or TIFF, a float OpenEXR).
WrittenImage save_map(const std::string& path, const vqtex_map_image& m) {
    if (m.bits > 8)
        return save_image16(path, m.image16.width, m.image16.height, m.image16.channels, m.image16.pixels,
                            space_of(m.kind));
    return save_image(path, m.image.width, m.image.height, m.image.channels, m.image.pixels, space_of(m.kind));
}

// A map of more than 8 bits written to a format of 8 (JPEG, TGA, BMP ...)
// loses what it was stored for: said on stderr (unless quiet) and in the
// JSON report's "notices".
void note_rounded(const Settings& s, FileReport& report, const std::string& output, const std::string& map,
                  uint32_t bits, const WrittenImage& written) {
    if (bits <= 8 || written.samples != "uint8") return;
    const std::string text = output + ": map '" + map + "' keeps " + std::to_string(bits) +
                             " bits, and this format holds 8: rounded to 8 (PNG, TIFF and OpenEXR keep them)";
    if (!report.json.contains("notices")) report.json["notices"] = nlohmann::ordered_json::array();
    report.json["notices"].push_back(text);
    if (!s.quiet) write_stderr("vqtex-decode: note: " + text + "\n");
}

// --coords writes OpenEXR (float) or TIFF (16 bits): formats that hold the
// coordinates whole, as the numbers they are. Throws for any other name.
void check_coords_name(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" && ext != ".tif" && ext != ".tiff")
        throw std::invalid_argument("--coords '" + path +
                                    "': the coordinates go to OpenEXR (.exr, 2 float channels) or TIFF (.tif, 2 "
                                    "channels of 16 bits), which hold them whole: give one of these extensions");
}

// The atlas coordinates of the decode `p` makes of `bytes` (the same size
// and seed as the texture), for --coords; an empty image without --coords.
// Decoded before any output is written, so that a file without coordinates
// (trees, an animation) leaves nothing behind.
vqtex_cpp::Image16 decode_coords(vqtex_decode_params p, const std::string& input, const std::vector<uint8_t>& bytes,
                                 const std::string& coords) {
    if (coords.empty()) return vqtex_cpp::Image16();
    // The texture's decode drew the progress bar; this one runs silent.
    p.progress = nullptr;
    p.progress_user = nullptr;
    vqtex_image16 raw{};
    vqtex_error err{};
    const vqtex_status st = vqtex_decode_coords(&p, bytes.data(), bytes.size(), &raw, &err);
    vqtex_cpp::Image16 grid(raw);  // owns the samples from here
    if (st != VQTEX_OK) throw std::runtime_error(input + ": --coords: " + err.detail);
    return grid;
}

WrittenImage save_coords(const std::string& path, const vqtex_cpp::Image16& grid) {
    return save_image16(path, grid.width(), grid.height(), grid.channels(), grid.data(), SampleSpace::positions);
}

// A write's error names the temporary it was given, or that one's own
// temporary: name the output instead.
std::string naming_output(std::string why, const std::string& staged, const std::string& output) {
    for (const std::string& from : {temporary_name_for(staged), staged})
        for (std::size_t at = 0; (at = why.find(from, at)) != std::string::npos; at += output.size())
            why.replace(at, from.size(), output);
    return why;
}

// Refuses a --coords file that is the input or one of the outputs.
void check_coords_target(const std::string& coords, const std::string& input, const std::vector<std::string>& outputs) {
    if (coords.empty()) return;
    std::error_code ec;
    if (fs::exists(coords, ec) && fs::equivalent(input, coords, ec))
        throw std::invalid_argument("--coords '" + coords + "' is the input itself: give another name");
    for (const std::string& output : outputs)
        if (output == coords || (fs::exists(coords, ec) && fs::equivalent(output, coords, ec)))
            throw std::invalid_argument("--coords '" + coords + "' is also the texture's output: give another name");
}

// What the JSON and text reports say of the coordinates written.
void report_coords(FileReport& report, const std::string& coords, const WrittenImage& written,
                   const vqtex_cpp::Image16& grid, const vqtex_file_info* info) {
    if (coords.empty()) return;
    auto& j = report.json;
    j["coords"] = coords;
    j["coords_samples"] = written.samples;
    std::string atlas;
    if (info && info->atlas_width) {
        j["atlas_width"] = info->atlas_width;
        j["atlas_height"] = info->atlas_height;
        atlas = " of the " + std::to_string(info->atlas_width) + "x" + std::to_string(info->atlas_height) + " atlas";
    }
    char line[1024];
    std::snprintf(line, sizeof line, "  coordinates -> %s (%ux%u, x and y%s, %s)\n", coords.c_str(), grid.width(),
                  grid.height(), atlas.c_str(), written.samples.c_str());
    report.text += line;
}

// Decodes every map of `input` (a file that is not a set gives one map,
// "texture") into `pattern` with {map} replaced by each map's name, and
// the coordinates into `coords` when given. Every file is written under a
// temporary name first and only then renamed into place, so a failed write
// leaves every existing file as it was; a failed rename (rare: folders are
// refused before) removes the files already renamed.
FileReport decode_maps_one(const Settings& s, const vqtex_decode_params& p, const std::string& input,
                           const std::vector<uint8_t>& bytes, const std::string& pattern, const vqtex_file_info* info,
                           ProgressBar* bar) {
    const std::string& coords = s.coords;
    std::vector<vqtex_map_image> maps(VQTEX_MAX_MAPS);
    uint32_t count = 0;
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st =
        vqtex_decode_maps(&p, bytes.data(), bytes.size(), maps.data(), uint32_t(maps.size()), &count, &err);
    // The library's images, released when these go out of scope.
    std::vector<vqtex_cpp::Image> owned;
    std::vector<vqtex_cpp::Image16> owned16;
    for (uint32_t i = 0; i < count; ++i) {
        owned.emplace_back(maps[i].image);
        owned16.emplace_back(maps[i].image16);
    }
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(input + ": " + err.detail);
    std::vector<std::string> names, outputs;
    for (uint32_t i = 0; i < count; ++i) {
        names.emplace_back(maps[i].name);
        outputs.push_back(map_output_name(pattern, names.back()));
        std::error_code ec;
        if (fs::exists(outputs.back(), ec) && fs::equivalent(input, outputs.back(), ec))
            throw std::invalid_argument("'" + outputs.back() + "' (map '" + names.back() +
                                        "') is the input itself: give another output name");
    }
    check_coords_target(coords, input, outputs);
    const double t_coords = now_seconds();
    const vqtex_cpp::Image16 grid = decode_coords(p, input, bytes, coords);
    // The files of this decode, the coordinates last.
    std::vector<std::string> targets = outputs;
    if (!coords.empty()) targets.push_back(coords);
    refuse_folders(targets);
    // OpenImageIO's load (first file of a call only) is timed apart from
    // the write: it is start-up, not work (docs/PERFORMANCE.md).
    const double t_load = now_seconds();
    load_image_io();
    const double t1 = now_seconds();
    std::vector<std::string> staged;  // written, not yet renamed into place
    std::vector<WrittenImage> written;
    std::size_t placed = 0;
    try {
        for (std::size_t i = 0; i < targets.size(); ++i) {
            staged.push_back(temporary_name_for(targets[i]));
            written.push_back(i < count ? save_map(staged.back(), maps[i]) : save_coords(staged.back(), grid));
        }
        for (; placed < targets.size(); ++placed) {
            std::error_code ec;
            fs::rename(staged[placed], targets[placed], ec);
            if (ec) throw std::runtime_error("cannot write '" + targets[placed] + "': " + ec.message());
        }
    } catch (const std::exception& e) {
        // The files of this decode go, renamed or not: all or nothing.
        std::error_code ec;
        for (std::size_t i = 0; i < staged.size(); ++i) fs::remove(i < placed ? targets[i] : staged[i], ec);
        throw std::runtime_error(staged.empty() ? std::string(e.what())
                                                : naming_output(e.what(), staged.back(), targets[staged.size() - 1]));
    }
    const uint32_t w = maps[0].bits > 8 ? maps[0].image16.width : maps[0].image.width;
    const uint32_t h = maps[0].bits > 8 ? maps[0].image16.height : maps[0].image.height;
    const double t2 = now_seconds();
    std::vector<uint32_t> bits;
    std::vector<std::string> samples, spaces;
    for (uint32_t i = 0; i < count; ++i) {
        bits.push_back(maps[i].bits);
        samples.push_back(written[i].samples);
        spaces.push_back(written[i].colour_space);
    }
    FileReport report;
    report.json = {{"input", input},
                   {"output", pattern},
                   {"bytes", bytes.size()},
                   {"width", w},
                   {"height", h},
                   {"bpp_output", 8.0 * double(bytes.size()) / (double(w) * h)},
                   {"maps", names},
                   {"outputs", outputs},
                   {"bits", bits},
                   {"samples", samples},
                   {"colour_spaces", spaces},
                   {"decode_seconds", t_coords - t0},
                   {"image_io_load_seconds", t1 - t_load},
                   {"write_seconds", t2 - t1}};
    if (!coords.empty()) report.json["coords_seconds"] = t_load - t_coords;
    char line[1024];
    std::snprintf(line, sizeof line, "%s (%zu bytes) -> %u map%s of %ux%u in %.3f s (%.2f Mpixel/s):\n", input.c_str(),
                  bytes.size(), count, count == 1 ? "" : "s", w, h, t_coords - t0,
                  double(w) * h / std::max(t_coords - t0, 1e-9) / 1e6);
    report.text = line;
    for (uint32_t i = 0; i < count; ++i) {
        const std::string depth =
            bits[i] > 8 ? " (" + std::to_string(bits[i]) + " bits, written as " + samples[i] + ")" : std::string();
        std::snprintf(line, sizeof line, "  %s -> %s%s\n", names[i].c_str(), outputs[i].c_str(), depth.c_str());
        report.text += line;
    }
    for (uint32_t i = 0; i < count; ++i) note_rounded(s, report, outputs[i], names[i], bits[i], written[i]);
    report_coords(report, coords, count < written.size() ? written.back() : WrittenImage{}, grid, info);
    return report;
}

// Decodes `input` into `output` with `threads` library threads; `bar` draws
// the per-stage progress of a single file (null in a batch). Throws a
// one-line message on failure.
FileReport decode_one(const Settings& s, const std::string& input, const std::string& output, unsigned threads,
                      ProgressBar* bar) {
    vqtex_decode_params p = s.params;
    p.threads = threads;
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    // The file is part of what the decode holds: a file above the limit is
    // refused before it is read whole.
    const std::vector<uint8_t> bytes = load_bytes(input, p.memory_limit, "raise --memory-limit if it is a .vqt file");
    FileReport report;
    char line[1024];
    if (s.frames || is_frame_pattern(output)) {
        if (has_map_field(output))
            throw std::invalid_argument("output '" + output +
                                        "': {map} names the maps of a material set and does not go with an "
                                        "animation's frames (--frames, or a frame-number field): drop one");
        if (s.mips) throw std::invalid_argument("--mips is not supported for animations");
        if (!s.coords.empty())
            throw std::invalid_argument("--coords is for still textures: an animation's frames have none; drop it");
        if (!is_frame_pattern(output))
            throw std::invalid_argument("output '" + output +
                                        "' needs one frame-number field for --frames, e.g. out/frame_%03d.png");
        vqtex_cpp::Volume v;  // owns the result
        vqtex_error err{};
        const double t0 = now_seconds();
        const vqtex_status st = vqtex_decode_volume(&p, s.frames, bytes.data(), bytes.size(), v.out(), &err);
        if (bar) bar->finish();
        if (st != VQTEX_OK) throw std::runtime_error(input + ": " + err.detail);
        const double t1 = now_seconds();
        const std::vector<std::string> written = save_sequence(output, v.get());
        const uint32_t w = v.width(), h = v.height(), n = v.frames();
        report.json = {{"input", input},       {"output", output},          {"bytes", bytes.size()},
                       {"width", w},           {"height", h},               {"frames", n},
                       {"decode_seconds", t1 - t0}, {"seconds_per_frame", (t1 - t0) / n}};
        std::snprintf(line, sizeof line, "%s (%zu bytes) -> %s .. %s, %u frames of %ux%u in %.3f s (%.3f s per frame)\n",
                      input.c_str(), bytes.size(), written.front().c_str(), written.back().c_str(), n, w, h, t1 - t0,
                      (t1 - t0) / n);
        report.text = line;
        return report;
    }
    if (has_map_field(output) && s.mips)
        throw std::invalid_argument("output '" + output +
                                    "': --mips does not go with {map} (the maps of a material set): drop one");
    // What the file holds: a set decoded into one file would silently be
    // its first map, a map's kind and bits decide how it is written, and
    // the coordinates' report names the atlas. A file inspect refuses goes
    // on to the decoder, which says why as it always has.
    vqtex_file_info info{};
    vqtex_error inspect_err{};
    const bool map_files = has_map_field(output);
    const bool inspected = (!map_files || !s.coords.empty()) &&
                           vqtex_inspect(bytes.data(), bytes.size(), p.memory_limit, &info, &inspect_err) == VQTEX_OK;
    if (map_files) return decode_maps_one(s, p, input, bytes, output, inspected ? &info : nullptr, bar);
    if (inspected && info.map_count > 1) {
        std::string names;
        for (uint32_t i = 0; i < info.map_count && i < VQTEX_MAX_MAPS; ++i)
            names += std::string(i ? ", " : "") + info.maps[i].name;
        const std::string what =
            input + " is a material set of " + std::to_string(info.map_count) + " maps (" + names + ")";
        if (s.mips)
            throw std::invalid_argument(what + ": --mips decodes single textures; decode the set without --mips, and " +
                                        map_field_hint(s) + " to write one file per map");
        throw std::invalid_argument(what + ": " + map_field_hint(s) + " to write one file per map");
    }
    // A file of one map: its kind says how it is written; a map of more
    // than 8 bits comes from vqtex_decode_maps, as vqtex_decode returns bytes.
    const bool one_map = inspected && info.map_count == 1;
    const uint32_t bits = one_map ? info.maps[0].bits : 8;
    const SampleSpace space = one_map ? space_of(info.maps[0].kind) : SampleSpace::colour;
    if (bits > 8 && s.mips)
        throw std::invalid_argument(input + ": map '" + info.maps[0].name + "' keeps " + std::to_string(bits) +
                                    " bits a sample, and --mips writes 8-bit levels: decode it without --mips "
                                    "(a 16-bit PNG or TIFF, or an OpenEXR)");
    check_coords_target(s.coords, input, {output});
    vqtex_error err{};
    const double t0 = now_seconds();
    std::vector<vqtex_image> levels(32);
    vqtex_map_image deep{};
    uint32_t count = 0;
    vqtex_status st;
    if (bits > 8) {
        st = vqtex_decode_maps(&p, bytes.data(), bytes.size(), &deep, 1, &count, &err);
    } else if (s.mips) {
        st = vqtex_decode_mips(&p, bytes.data(), bytes.size(), levels.data(), uint32_t(levels.size()), &count, &err);
    } else {
        st = vqtex_decode(&p, bytes.data(), bytes.size(), &levels[0], &err);
        count = st == VQTEX_OK ? 1 : 0;
    }
    // The library's images, released when these go out of scope.
    std::vector<vqtex_cpp::Image> owned;
    for (uint32_t i = 0; i < count && bits == 8; ++i) owned.emplace_back(levels[i]);
    const vqtex_cpp::Image16 owned16(deep.image16);
    const vqtex_cpp::Image owned_deep8(deep.image);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(input + ": " + err.detail);
    const double t_coords = now_seconds();
    const vqtex_cpp::Image16 grid = decode_coords(p, input, bytes, s.coords);
    // OpenImageIO's load (first file of a call only) is timed apart from
    // the write: it is start-up, not work (docs/PERFORMANCE.md).
    const double t_load = now_seconds();
    load_image_io();
    const double t1 = now_seconds();
    // The coordinates go to a temporary name first and into place after
    // the texture, so that a failed texture leaves them unwritten too.
    std::string coords_staged;
    WrittenImage coords_written;
    if (!s.coords.empty()) {
        refuse_folders({s.coords});
        coords_staged = temporary_name_for(s.coords);
        try {
            coords_written = save_coords(coords_staged, grid);
        } catch (const std::exception& e) {
            throw std::runtime_error(naming_output(e.what(), coords_staged, s.coords));
        }
    }
    std::vector<std::string> written;
    WrittenImage texture;
    try {
        if (bits > 8) {
            texture = save_map(output, deep);
            written.push_back(output);
        } else if (s.mips) {
            written = save_mip_chain(output, levels.data(), count, space, &texture);
        } else {
            const vqtex_image& level = levels[0];
            texture = save_image(output, level.width, level.height, level.channels, level.pixels, space);
            written.push_back(output);
        }
        if (!coords_staged.empty()) {
            std::error_code ec;
            fs::rename(coords_staged, s.coords, ec);
            if (ec) throw std::runtime_error("cannot write '" + s.coords + "': " + ec.message());
        }
    } catch (...) {
        std::error_code ec;
        if (!coords_staged.empty()) fs::remove(coords_staged, ec);
        throw;
    }
    const uint32_t w = bits > 8 ? owned16.width() : levels[0].width, h = bits > 8 ? owned16.height() : levels[0].height;
    const double t2 = now_seconds();
    report.json = {{"input", input},
                   {"output", output},
                   {"bytes", bytes.size()},
                   {"width", w},
                   {"height", h},
                   {"bpp_output", 8.0 * double(bytes.size()) / (double(w) * h)},
                   {"levels_written", bits > 8 ? 1u : count},
                   {"bits", bits},
                   {"samples", texture.samples},
                   {"colour_space", texture.colour_space},
                   {"decode_seconds", t_coords - t0},
                   {"image_io_load_seconds", t1 - t_load},
                   {"write_seconds", t2 - t1}};
    if (!s.coords.empty()) report.json["coords_seconds"] = t_load - t_coords;
    const std::string depth = bits > 8 ? ", " + std::to_string(bits) + " bits written as " + texture.samples : "";
    std::snprintf(line, sizeof line, "%s (%zu bytes) -> %s %ux%u%s%s in %.3f s (%.2f Mpixel/s)\n", input.c_str(),
                  bytes.size(), written.front().c_str(), w, h, s.mips ? " with mip chain" : "", depth.c_str(),
                  t_coords - t0, double(w) * h / std::max(t_coords - t0, 1e-9) / 1e6);
    report.text = line;
    if (bits > 8) note_rounded(s, report, output, info.maps[0].name, bits, texture);
    report_coords(report, s.coords, coords_written, grid, inspected ? &info : nullptr);
    return report;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-decode: synthesise a tileable texture of any size from a .vqt file.\n"
                 "Example: vqtex-decode cellular.vqt cellular_1024.png --size 1024x1024\n"
                 "Batch:   vqtex-decode textures/ more.vqt -o out/ --size 512 --format exr"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string size, out_dir, format = "png", suffix, coords;
    uint64_t seed = 0, memory_mib = 1024;
    uint32_t threads = 0;
    int png_compression = WriteOptions{}.png_compression;
    bool mips = false, json = false, quiet = false;
    uint32_t frames = 0;
    auto* seed_opt = app.add_option("--seed", seed, "seed (default: the file's)");
    app.add_option("files", files,
                   "INPUT.vqt OUTPUT (format from the extension; {map} in OUTPUT writes one file per map of a "
                   "material set, e.g. 'out_{map}.png'), or with -o: .vqt files and folders of them")
        ->required();
    auto* out_dir_opt = app.add_option("-o,--output-dir", out_dir,
                                       "batch: write OUTDIR/NAME[SUFFIX].FORMAT for every input (created if missing)");
    app.add_option("--format", format, "batch: output format, as a file extension")->capture_default_str();
    app.add_option("--suffix", suffix, "batch: text added to each output's name, e.g. _1k ({map}: one file per map)");
    app.add_option("-s,--size", size, "output size WxH, 1 to 16384 per side (default: the example's size)");
    app.add_option("--frames", frames,
                   "animated texture: frames to write (1 to 16384; default: the example's count); the output "
                   "name needs a frame-number field, e.g. out/frame_%03d.png (batch: NAME_%04d.FORMAT)")
        ->check(CLI::Range(1, 16384));
    app.add_option("--coords", coords,
                   "also write the atlas coordinates of the decode (same size and seed): for every output pixel "
                   "the (x, y) of the atlas pixel it is read from, to apply the layout to maps of your own; "
                   ".exr (2 float channels) or .tif (2 channels of 16 bits)");
    app.add_flag("--mips", mips,
                 "write the whole mip chain: one MIP-mapped file for .tif/.exr, else OUT_mipN.ext per level");
    app.add_option("--png-compression", png_compression,
                   "zlib level of PNG outputs, 0 (fastest) to 9 (smallest files)")
        ->check(CLI::Range(0, 9))
        ->capture_default_str();
    app.add_option("-j,--threads", threads,
                   "threads (default: all cores), shared between the files of a batch; output is identical");
    app.add_option("--memory-limit", memory_mib, "MiB the decoder may allocate (per file), 1 to 16777216")
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 24))
        ->capture_default_str();
    app.add_flag("--json", json, "print machine-readable statistics on stdout (one JSON line per file)");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    CLI11_PARSE(app, argc, argv);

    try {
        Settings s;
        vqtex_decode_params_init(&s.params);
        if (!size.empty()) parse_size(size, s.params.width, s.params.height);
        if (*seed_opt) s.params.seed = seed;
        s.params.memory_limit = memory_mib << 20;
        s.frames = frames;
        s.mips = mips;
        s.batch = bool(*out_dir_opt);
        s.coords = coords;
        s.quiet = quiet;
        if (!coords.empty()) {
            check_coords_name(coords);
            if (s.batch)
                throw std::invalid_argument("--coords names one file: decode one input (INPUT.vqt OUTPUT) with it, "
                                            "not a batch");
        }
        WriteOptions write;
        write.png_compression = png_compression;
        set_write_options(write);

        if (!*out_dir_opt) {
            require_single_pair(files, "OUTPUT", "decode", "inputs");
            ProgressBar bar(!quiet && !json);
            const FileReport r = decode_one(s, files[0], files[1], threads, &bar);
            print_report(r, json, quiet);
            return 0;
        }

        // Batch: every input gets its output name; two inputs that would
        // write the same file are an error for the second.
        prepare_output_folder(out_dir);
        const std::vector<std::string> inputs = expand_inputs(files, {".vqt"});
        BatchOutputs outputs(inputs);
        for (const std::string& in : inputs)
            outputs.add(batch_output_name(in, out_dir, frames ? suffix + "_%04d" : suffix, format));
        return run_batch(inputs.size(), batch_options("vqtex-decode", threads, json, quiet, inputs),
                         [&](std::size_t i, unsigned per_file) {
            outputs.check_first(i, "decode");
            check_batch_pair(inputs[i], outputs[i], ".vqt file");
            return decode_one(s, inputs[i], outputs[i], per_file, nullptr);
        });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-decode: error: %s\n", e.what());
        return 1;
    }
}
