// vqtex-bench's animation protocol (see animation_protocol.hpp).
#include "animation_protocol.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/atlas_choice.hpp"
#include "anim_examples.hpp"
#include "anim_pictures.hpp"
#include "anim_stats.hpp"
#include "animation_rows.hpp"
#include "animation_summary.hpp"
#include "format/atlas_coder.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"
#include "writer/atlas_encoder.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

constexpr uint32_t kThreads = 2;
constexpr int kSequenceSpeed = 6;  // libaom's speed for av1+synth, the encoder's own for animations
const std::vector<uint64_t> kDefaultTargets{4000, 16000, 64000};
// The shared corpus's photographs made into animations: water, caustics.
const char* const kPhotographs[] = {"tux_oceansplash_256", "embark_caustics_256"};

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The frames as one buffer, frame after frame, and the library's view of it.
struct Volume {
    std::vector<uint8_t> pixels;
    vqtex_volume view{};
    Volume(const Volume&) = delete;
    Volume& operator=(const Volume&) = delete;
    explicit Volume(const Frames& frames) {
        for (const Image& f : frames) pixels.insert(pixels.end(), f.pixels.begin(), f.pixels.end());
        view = {uint32_t(frames[0].width), uint32_t(frames[0].height), uint32_t(frames.size()),
                uint32_t(frames[0].channels), pixels.data()};
    }
};

// Takes the library's volume (and releases it).
Frames frames_from_c(vqtex_volume& v) {
    Frames f = split_frames(v.pixels, v.width, v.height, v.channels, v.frames);
    vqtex_volume_free(&v);
    return f;
}

// One run's outcome: the output frames, or why there are none.
struct Output {
    Frames frames;
    std::string status = "ok";
    std::size_t bytes = 0;
    std::string setting;
    double encode_s = 0, decode_s = 0;
};

// The coherent engine from an example sequence, as the ceiling and
// av1+synth both use it (the library's defaults, seed and size as asked).
bool synthesise_volume(const Frames& example, int side, uint32_t frames, uint64_t seed, Frames& out) {
    Volume in(example);
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.width = uint32_t(side);
    p.height = uint32_t(side);
    p.seed = seed;
    p.threads = kThreads;
    vqtex_volume v{};
    vqtex_error err{};
    if (vqtex_synthesize_volume(&p, &in.view, frames, &v, nullptr, &err) != VQTEX_OK) {
        std::fprintf(stderr, "vqtex-bench: error: synthesis: %s\n", err.detail);
        return false;
    }
    out = frames_from_c(v);
    return true;
}

Output run_ceiling(const Frames& example, int side, uint32_t frames, uint64_t seed) {
    Output o;
    const auto start = std::chrono::steady_clock::now();
    if (!synthesise_volume(example, side, frames, seed, o.frames)) o.status = "failed";
    o.decode_s = seconds_since(start);
    return o;
}

// vqtex_encode_volume (the default quality when target is 0), then
// vqtex_decode_volume.
Output run_vqtex(const Frames& example, uint64_t target, int side, uint32_t frames, uint64_t seed) {
    Output o;
    o.setting = target ? "--target-size " + std::to_string(target) : "default";
    Volume in(example);
    vqtex_volume_encode_params ep;
    vqtex_volume_encode_params_init(&ep);
    ep.target_size = target;
    ep.threads = kThreads;
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    auto start = std::chrono::steady_clock::now();
    const vqtex_status status = vqtex_encode_volume(&ep, &in.view, &data, &size, nullptr, &err);
    o.encode_s = seconds_since(start);
    if (status != VQTEX_OK) {
        o.status = status == VQTEX_ERROR_LIMIT_EXCEEDED ? "limit-exceeded" : "failed";
        std::fprintf(stderr, "vqtex-bench: %s: encode (%s): %s\n",
                     status == VQTEX_ERROR_LIMIT_EXCEEDED ? "note" : "error", o.setting.c_str(), err.detail);
        return o;
    }
    o.bytes = size;
    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    dp.width = uint32_t(side);
    dp.height = uint32_t(side);
    dp.seed = seed;
    dp.threads = kThreads;
    vqtex_volume v{};
    start = std::chrono::steady_clock::now();
    const vqtex_status decoded = vqtex_decode_volume(&dp, frames, data, size, &v, &err);
    o.decode_s = seconds_since(start);
    vqtex_free(data);
    if (decoded != VQTEX_OK) {
        o.status = "failed";
        std::fprintf(stderr, "vqtex-bench: error: decode (%s): %s\n", o.setting.c_str(), err.detail);
        return o;
    }
    o.frames = frames_from_c(v);
    return o;
}

// The whole example as one AV1 sequence at the finest level that fits
// `budget` bytes, decoded and synthesised by the coherent engine.
Output run_av1_synth(const Frames& example, std::size_t budget, int side, uint32_t frames, uint64_t seed) {
    Output o;
    try {
        std::vector<vqtex::Image> sequence;
        for (const Image& f : example) {
            vqtex::Image im(f.width, f.height, f.channels);
            im.pixels = f.pixels;
            sequence.push_back(std::move(im));
        }
        std::map<int, std::vector<uint8_t>> coded;
        const auto bitstream = [&](int cq) -> const std::vector<uint8_t>& {
            auto it = coded.find(cq);
            if (it != coded.end()) return it->second;
            vqtex::AtlasEncodeOptions opts;
            opts.cq_level = cq;
            opts.speed = kSequenceSpeed;
            return coded[cq] = vqtex::encode_atlas_frames(sequence, opts);
        };
        auto start = std::chrono::steady_clock::now();
        const int cq = vqtex::finest_fitting_level(budget, [&](int q) { return bitstream(q).size(); });
        o.encode_s = seconds_since(start);
        if (cq < 0) {
            o.status = "no-fit";
            o.setting = "no level fits";
            return o;
        }
        const std::vector<uint8_t>& bits = bitstream(cq);
        o.bytes = bits.size();
        o.setting = "cq " + std::to_string(cq);
        start = std::chrono::steady_clock::now();
        const std::vector<vqtex::Image> decoded =
            vqtex::decode_atlas_frames(bits.data(), bits.size(), example[0].width, example[0].height,
                                       example[0].channels, int(example.size()), "av1+synth");
        Frames lossy;
        for (const vqtex::Image& f : decoded) lossy.push_back(Image{f.width, f.height, f.channels, f.pixels});
        if (!synthesise_volume(lossy, side, frames, seed, o.frames)) o.status = "failed";
        o.decode_s = seconds_since(start);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-bench: error: av1+synth: %s\n", e.what());
        o.status = "failed";
    }
    return o;
}

// The animations: the folder's, then the photographs' when found.
bool list_animations(const BenchOptions& o, std::vector<AnimExample>& out) {
    try {
        out = corpus_animations(o.folder);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-bench: error: %s\n", e.what());
        return false;
    }
    if (out.empty()) {
        std::fprintf(stderr, "vqtex-bench: error: no NAME_anim/ frame sequences in %s\n", o.folder.c_str());
        return false;
    }
    std::error_code ec;
    if (o.shared.empty()) {
        std::fprintf(stderr, "vqtex-bench: note: --shared '': the photograph animations are skipped\n");
        return true;
    }
    for (const char* stem : kPhotographs) {
        const fs::path path = fs::path(o.shared) / (std::string(stem) + ".png");
        if (!fs::exists(path, ec)) {
            std::fprintf(stderr, "vqtex-bench: note: %s not found: its animation is skipped (--shared DIR)\n",
                         path.string().c_str());
            continue;
        }
        try {
            const LoadedImage li = load_image(path.string());
            const Image photo{int(li.width), int(li.height), int(li.channels), li.pixels};
            AnimExample a;
            a.name = std::string(stem) + "_pan";
            a.frames = photograph_animation(photo);
            a.output_side = a.frames[0].width;
            out.push_back(std::move(a));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", path.string().c_str(), e.what());
            return false;
        }
    }
    return true;
}

std::string file_label(const std::string& codec, uint64_t target) {
    return (codec == "av1+synth" ? std::string("av1synth") : codec) +
           (codec == "ceiling" ? std::string() : "_" + (target ? std::to_string(target) : std::string("default")));
}

}  // namespace

int run_animation_protocol(const BenchOptions& o) {
    std::vector<AnimExample> animations;
    if (!list_animations(o, animations)) return 1;
    FILE* csv = nullptr;
    if (!o.csv.empty() && !(csv = std::fopen(o.csv.c_str(), "w"))) {
        std::fprintf(stderr, "vqtex-bench: error: cannot write %s\n", o.csv.c_str());
        return 1;
    }
    AnimWriter writer(csv);
    char dir_template[] = "/tmp/vqtex_animation_XXXXXX";
    if (!::mkdtemp(dir_template)) {
        std::fprintf(stderr, "vqtex-bench: error: cannot make a temporary folder\n");
        return 1;
    }
    const fs::path scratch(dir_template);
    // The rate points: the default quality, then each target (0 in
    // --target-sizes: the default alone).
    std::vector<uint64_t> targets{0};
    for (uint64_t t : o.target_sizes.empty() ? kDefaultTargets : o.target_sizes)
        if (t) targets.push_back(t);
    const uint32_t frames = o.anim_frames;
    AnimStatsOptions measure;
    measure.coherence = measure.seam_visibility = true;
    measure.seed = o.seed;
    measure.threads = int(kThreads);
    if (!o.sheets.empty()) fs::create_directories(o.sheets);
    const auto total_start = std::chrono::steady_clock::now();
    for (const AnimExample& a : animations) {
        const auto anim_start = std::chrono::steady_clock::now();
        const double floor = swd_floor(a.frames);
        std::vector<Frames> sheet_rows{a.frames};
        std::vector<std::string> sheet_labels{"example"};
        const auto add = [&](const std::string& codec, uint64_t target, const Output& out) {
            AnimRow r;
            r.animation = a.name;
            r.codec = codec;
            r.target = target;
            r.setting = out.setting;
            r.status = out.status;
            r.bytes = out.bytes;
            r.width = r.height = a.output_side;
            r.frames = int(frames);
            r.swd_floor = floor;
            r.encode_s = o.no_times ? 0 : out.encode_s;
            r.decode_s = o.no_times ? 0 : out.decode_s;
            double measure_s = 0;
            if (r.status == "ok") {
                const auto start = std::chrono::steady_clock::now();
                try {
                    r.stats = anim_stats(a.frames, out.frames, measure);
                    measure_s = seconds_since(start);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "vqtex-bench: error: %s %s: measures: %s\n", a.name.c_str(), codec.c_str(),
                                 e.what());
                    r.status = "failed";
                }
            }
            if (r.status == "ok") {
                std::fprintf(stderr,
                             "vqtex-bench: %s %s %s: %zu bytes, encode %.2f s, decode %.2f s, measures %.1f s\n",
                             a.name.c_str(), codec.c_str(), out.setting.c_str(), out.bytes, out.encode_s, out.decode_s,
                             measure_s);
                if (!o.sheets.empty()) {
                    sheet_rows.push_back(out.frames);
                    sheet_labels.push_back(codec + (codec == "ceiling" ? "" : " " + out.setting));
                    write_animated_webp(
                        fs::path(o.sheets) / ("anim_" + a.name + "_" + file_label(codec, target) + ".webp"), out.frames,
                        scratch);
                }
            }
            writer.add(r);
        };
        if (!o.sheets.empty())
            write_animated_webp(fs::path(o.sheets) / ("anim_" + a.name + "_example.webp"), a.frames, scratch);
        add("ceiling", 0, run_ceiling(a.frames, a.output_side, frames, o.seed));
        for (uint64_t target : targets) {
            const Output v = run_vqtex(a.frames, target, a.output_side, frames, o.seed);
            add("vqtex", target, v);
            if (v.status == "ok")
                add("av1+synth", target, run_av1_synth(a.frames, v.bytes, a.output_side, frames, o.seed));
        }
        if (!o.sheets.empty()) {
            const fs::path sheet = fs::path(o.sheets) / ("anim_" + a.name + ".png");
            write_animation_sheet(sheet, sheet_rows);
            std::string legend;
            for (const std::string& l : sheet_labels) legend += (legend.empty() ? "" : " | ") + l;
            std::printf("sheet %s: frames 0, 4, ..., 28 of each row, top to bottom: %s\n", sheet.string().c_str(),
                        legend.c_str());
        }
        std::printf("%s: %zu example frames of %dx%d, outputs %dx%dx%u, %.1f s\n", a.name.c_str(), a.frames.size(),
                    a.frames[0].width, a.frames[0].height, a.output_side, a.output_side, frames,
                    seconds_since(anim_start));
        std::fflush(stdout);
    }
    if (csv) std::fclose(csv);
    std::error_code ec;
    fs::remove_all(scratch, ec);
    print_animation_summary(writer.rows);
    std::printf("\nanimation protocol: %zu animations, %.1f s\n", animations.size(), seconds_since(total_start));
    return 0;
}

}  // namespace vqtex_tools
