// vqtex-decode - regenerate a texture of any size from a .vqt file by
// synthesis (paper section 6), through the public API only. One file
// (`vqtex-decode IN OUT`) or a batch (`vqtex-decode IN... -o DIR`); a
// material set's maps to one file each (`vqtex-decode IN 'out_{map}.png'`).
#include <algorithm>
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

// Decodes every map of `input` (a file that is not a set gives one map,
// "texture") into `pattern` with {map} replaced by each map's name. Every
// map is written under a temporary name first and only then renamed into
// place, so a failed write leaves every existing file as it was; a failed
// rename (rare: folders are refused before) removes the maps already renamed.
FileReport decode_maps_one(const vqtex_decode_params& p, const std::string& input, const std::vector<uint8_t>& bytes,
                           const std::string& pattern, ProgressBar* bar) {
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
        // The image I/O writes 8-bit samples only: a 12-bit map would lose
        // what it was stored for.
        if (maps[i].bits > 8)
            throw std::runtime_error(input + ": map '" + maps[i].name + "' has " + std::to_string(maps[i].bits) +
                                     "-bit samples, and vqtex-decode writes 8-bit images only: decode it with "
                                     "the library (vqtex_decode_maps)");
        names.emplace_back(maps[i].name);
        outputs.push_back(map_output_name(pattern, names.back()));
        std::error_code ec;
        if (fs::exists(outputs.back(), ec) && fs::equivalent(input, outputs.back(), ec))
            throw std::invalid_argument("'" + outputs.back() + "' (map '" + names.back() +
                                        "') is the input itself: give another output name");
    }
    refuse_folders(outputs);
    // OpenImageIO's load (first file of a call only) is timed apart from
    // the write: it is start-up, not work (docs/PERFORMANCE.md).
    const double t_load = now_seconds();
    load_image_io();
    const double t1 = now_seconds();
    std::vector<std::string> staged;  // written, not yet renamed into place
    std::size_t placed = 0;
    try {
        for (uint32_t i = 0; i < count; ++i) {
            const vqtex_image& m = maps[i].image;
            staged.push_back(temporary_name_for(outputs[i]));
            save_image(staged.back(), m.width, m.height, m.channels, m.pixels);
        }
        for (; placed < outputs.size(); ++placed) {
            std::error_code ec;
            fs::rename(staged[placed], outputs[placed], ec);
            if (ec) throw std::runtime_error("cannot write '" + outputs[placed] + "': " + ec.message());
        }
    } catch (const std::exception& e) {
        // The outputs of this decode go, renamed or not: all or nothing.
        std::error_code ec;
        for (std::size_t i = 0; i < staged.size(); ++i) fs::remove(i < placed ? outputs[i] : staged[i], ec);
        // A failed write names the file it was given, a temporary, or that
        // one's own temporary: name the output instead.
        std::string why = e.what();
        if (!staged.empty()) {
            const std::string& output = outputs[staged.size() - 1];
            for (const std::string& from : {temporary_name_for(staged.back()), staged.back()})
                for (std::size_t at = 0; (at = why.find(from, at)) != std::string::npos; at += output.size())
                    why.replace(at, from.size(), output);
        }
        throw std::runtime_error(why);
    }
    const uint32_t w = maps[0].image.width, h = maps[0].image.height;
    const double t2 = now_seconds();
    FileReport report;
    report.json = {{"input", input},
                   {"output", pattern},
                   {"bytes", bytes.size()},
                   {"width", w},
                   {"height", h},
                   {"bpp_output", 8.0 * double(bytes.size()) / (double(w) * h)},
                   {"maps", names},
                   {"outputs", outputs},
                   {"decode_seconds", t_load - t0},
                   {"image_io_load_seconds", t1 - t_load},
                   {"write_seconds", t2 - t1}};
    char line[1024];
    std::snprintf(line, sizeof line, "%s (%zu bytes) -> %u map%s of %ux%u in %.3f s (%.2f Mpixel/s):\n", input.c_str(),
                  bytes.size(), count, count == 1 ? "" : "s", w, h, t_load - t0,
                  double(w) * h / std::max(t_load - t0, 1e-9) / 1e6);
    report.text = line;
    for (uint32_t i = 0; i < count; ++i) {
        std::snprintf(line, sizeof line, "  %s -> %s\n", names[i].c_str(), outputs[i].c_str());
        report.text += line;
    }
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
    if (has_map_field(output)) {
        if (s.frames || is_frame_pattern(output))
            throw std::invalid_argument("output '" + output +
                                        "': {map} names the maps of a material set and does not go with an "
                                        "animation's frames (--frames, or a frame-number field): drop one");
        if (s.mips)
            throw std::invalid_argument("output '" + output +
                                        "': --mips does not go with {map} (the maps of a material set): drop one");
        return decode_maps_one(p, input, bytes, output, bar);
    }
    if (s.frames || is_frame_pattern(output)) {
        if (s.mips) throw std::invalid_argument("--mips is not supported for animations");
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
    // A set decoded into one file would silently be its first map. A file
    // inspect refuses goes on to the decoder, which says why as it always has.
    vqtex_file_info info{};
    vqtex_error inspect_err{};
    if (vqtex_inspect(bytes.data(), bytes.size(), p.memory_limit, &info, &inspect_err) == VQTEX_OK &&
        info.map_count > 1) {
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
    vqtex_error err{};
    const double t0 = now_seconds();
    std::vector<vqtex_image> levels(32);
    uint32_t count = 0;
    vqtex_status st;
    if (s.mips) {
        st = vqtex_decode_mips(&p, bytes.data(), bytes.size(), levels.data(), uint32_t(levels.size()), &count, &err);
    } else {
        st = vqtex_decode(&p, bytes.data(), bytes.size(), &levels[0], &err);
        count = st == VQTEX_OK ? 1 : 0;
    }
    // The library's images, released when these go out of scope.
    std::vector<vqtex_cpp::Image> owned;
    for (uint32_t i = 0; i < count; ++i) owned.emplace_back(levels[i]);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(input + ": " + err.detail);
    // OpenImageIO's load (first file of a call only) is timed apart from
    // the write: it is start-up, not work (docs/PERFORMANCE.md).
    const double t_load = now_seconds();
    load_image_io();
    const double t1 = now_seconds();
    std::vector<std::string> written;
    if (s.mips) {
        written = save_mip_chain(output, levels.data(), count);
    } else {
        save_image(output, levels[0].width, levels[0].height, levels[0].channels, levels[0].pixels);
        written.push_back(output);
    }
    const uint32_t w = levels[0].width, h = levels[0].height;
    const double t2 = now_seconds();
    report.json = {{"input", input},
                   {"output", output},
                   {"bytes", bytes.size()},
                   {"width", w},
                   {"height", h},
                   {"bpp_output", 8.0 * double(bytes.size()) / (double(w) * h)},
                   {"levels_written", count},
                   {"decode_seconds", t_load - t0},
                   {"image_io_load_seconds", t1 - t_load},
                   {"write_seconds", t2 - t1}};
    std::snprintf(line, sizeof line, "%s (%zu bytes) -> %s %ux%u%s in %.3f s (%.2f Mpixel/s)\n", input.c_str(),
                  bytes.size(), written.front().c_str(), w, h, s.mips ? " with mip chain" : "", t_load - t0,
                  double(w) * h / std::max(t_load - t0, 1e-9) / 1e6);
    report.text = line;
    return report;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-decode: synthesise a tileable texture of any size from a .vqt file.\n"
                 "Example: vqtex-decode cellular.vqt cellular_1024.png --size 1024x1024\n"
                 "Batch:   vqtex-decode textures/ more.vqt -o out/ --size 512 --format exr"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string size, out_dir, format = "png", suffix;
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
