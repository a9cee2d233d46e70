// vqtex-bench's compact protocol (see compact_protocol.hpp).
#include "compact_protocol.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "analysis/atlas_choice.hpp"
#include "bench_images.hpp"
#include "bench_peers.hpp"
#include "bench_rows.hpp"
#include "contact_sheet.hpp"
#include "image_io.hpp"
#include "inverse_synthesis.hpp"
#include "measured_run.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"
#include "vqtex_runs.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

constexpr uint32_t kEncodeThreads = 2;
const std::vector<uint64_t> kDefaultTargets{4000, 8000, 16000, 32000};

// The protocol's scores of an output against the input itself. Every
// window of the images is a candidate: the metrics' default stride above
// 512x512 misses verbatim copies off the stride, and scored a blurred
// output above synthesis from the lossless input.
AllScores compact_scores(const Image& output, const Image& input, uint64_t seed) {
    AllScores s;
    const int every_output_window = output.width * output.height, every_input_window = input.width * input.height;
    s.swd = vqtex_metrics::sliced_wasserstein(output, input, 4, 7, 64, seed);
    s.completeness = vqtex_metrics::completeness(input, output, 7, 256, seed, every_output_window);
    s.coherence = vqtex_metrics::coherence(output, input, 7, 256, seed, every_input_window);
    s.seams.coherence_half = vqtex_metrics::coherence_half_resolution(output, input, 7, 256, seed);
    s.seam_ratio = vqtex_metrics::seam_ratio(output);
    return s;
}

// A file decoded at w x h (empty when it does not decode).
Image decode_file(const std::vector<uint8_t>& file, int w, int h, uint64_t seed) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = uint32_t(w);
    p.height = uint32_t(h);
    p.seed = seed;
    p.threads = kEncodeThreads;
    vqtex_image out{};
    vqtex_error err{};
    if (vqtex_decode(&p, file.data(), file.size(), &out, &err) != VQTEX_OK) {
        std::fprintf(stderr, "vqtex-bench: error: decode: %s\n", err.detail);
        return {};
    }
    return from_c(out);
}

struct Encoded {
    std::vector<uint8_t> file;
    double seconds = 0;
    long peak_kib = 0;
    bool ok = false;
};

// vqtex's encoder through the public API (quality when target is 0), in a
// measured child.
Encoded encode_public(const Image& input, uint64_t target, const fs::path& scratch) {
    Encoded e;
    const std::string path = (scratch / "compact.vqt").string();
    Image in = input;
    e.ok = measured([&] {
        vqtex_encode_params ep;
        vqtex_encode_params_init(&ep);
        ep.target_size = target;
        ep.threads = kEncodeThreads;
        vqtex_image ex = view(in);
        uint8_t* data = nullptr;
        size_t size = 0;
        vqtex_error err{};
        if (vqtex_encode(&ep, &ex, &data, &size, nullptr, &err) != VQTEX_OK) {
            std::fprintf(stderr, "vqtex-bench: error: encode: %s\n", err.detail);
            return false;
        }
        const vqtex_cpp::Buffer owned(data, size);
        return write_all(path, owned.data(), owned.size());
    }, e.peak_kib, e.seconds);
    if (e.ok) e.file = read_all(path);
    return e;
}

// The encoder's rule before it coded parts of large examples (see
// compact_protocol.hpp), in a measured child.
Encoded encode_crop_rule(const Image& input, uint64_t target, const fs::path& scratch) {
    Encoded e;
    const std::string path = (scratch / "crop.vqt").string();
    e.ok = measured([&] {
        vqtex::Image ex(input.width, input.height, input.channels);
        ex.pixels = input.pixels;
        vqtex::AtlasChoiceOptions o;
        o.budget = target ? target : vqtex::atlas_budget_of_quality(50, ex.pixel_count());
        o.threads = int(kEncodeThreads);
        o.compaction = false;
        try {
            const vqtex::AtlasChoice c = vqtex::choose_atlas(ex, o);
            return write_all(path, c.file.data(), c.file.size());
        } catch (const std::exception& x) {
            std::fprintf(stderr, "vqtex-bench: crop rule: %s\n", x.what());
            return false;
        }
    }, e.peak_kib, e.seconds);
    if (e.ok) e.file = read_all(path);
    return e;
}

void add_row(Writer& writer, const std::string& texture, const std::string& codec, int quality,
             const std::string& setting, const Encoded* e, std::size_t bytes, const Image& output,
             const Image& input, uint64_t seed) {
    Row r;
    r.texture = texture;
    r.protocol = "compact";
    r.codec = codec;
    r.quality = quality;
    r.setting = setting;
    r.bytes = bytes;
    r.bpp_exemplar = 8.0 * double(bytes) / (double(input.width) * input.height);
    r.bpp_output = r.bpp_exemplar;
    if (e) {
        r.encode_s = e->seconds;
        r.encode_peak_kib = e->peak_kib;
    }
    if (output.pixels.empty()) {
        r.status = "failed";
    } else {
        r.scores = compact_scores(output, input, seed);
    }
    writer.add(r, AllScores{});
}

void summarise(const std::vector<Row>& rows) {
    // codec, quality -> sums
    struct Sum {
        double compl_ = 0, swd = 0, coh = 0, half = 0, bytes = 0, enc = 0, peak = 0;
        int n = 0;
    };
    std::map<std::pair<int, std::string>, Sum> sums;
    for (const Row& r : rows) {
        if (r.protocol != "compact" || r.status != "ok") continue;
        Sum& s = sums[{r.quality, r.codec}];
        s.compl_ += r.scores.completeness;
        s.swd += r.scores.swd.mean;
        s.coh += r.scores.coherence;
        s.half += r.scores.seams.coherence_half;
        s.bytes += double(r.bytes);
        s.enc += r.encode_s;
        s.peak = std::max(s.peak, double(r.encode_peak_kib));
        ++s.n;
    }
    std::printf("\ncompact protocol (outputs at the input's size, scored against the input; means; "
                "target 0 = the default; encode on %u threads, peak = the largest)\n", kEncodeThreads);
    std::printf("%-7s %-18s %3s %9s %8s %7s %7s %7s %8s %9s\n", "target", "codec", "n", "bytes", "compl", "swd", "coher",
                "coh_1/2", "enc_s", "peak_MiB");
    for (const auto& [key, s] : sums)
        std::printf("%-7d %-18s %3d %9.0f %8.3f %7.3f %7.3f %7.3f %8.2f %9.1f\n", key.first, key.second.c_str(), s.n,
                    s.bytes / s.n, s.compl_ / s.n, s.swd / s.n, s.coh / s.n, s.half / s.n, s.enc / s.n,
                    s.peak / 1024.0);
}

// An image of at most 256x256: the tile alone and its 4x4 tiling at the
// default.
void run_tiling(Writer& writer, const std::string& name, const Image& tile, const fs::path& scratch, uint64_t seed) {
    const Encoded alone = encode_public(tile, 0, scratch);
    const Image sheet = tiled(tile, tile.width * 4, tile.height * 4);
    const Encoded tiling = encode_public(sheet, 0, scratch);
    const Image out_alone = alone.ok ? decode_file(alone.file, sheet.width, sheet.height, seed) : Image{};
    const Image out_tiling = tiling.ok ? decode_file(tiling.file, sheet.width, sheet.height, seed) : Image{};
    add_row(writer, name, "tile-alone", 0, "default", &alone, alone.file.size(), out_alone, tile, seed);
    add_row(writer, name, "tiling-4x4", 0, "default", &tiling, tiling.file.size(), out_tiling, tile, seed);
    std::printf("%s: tile alone %zu bytes, its 4x4 tiling %zu bytes (%.3fx)\n", name.c_str(), alone.file.size(),
                tiling.file.size(), alone.file.empty() ? 0.0 : double(tiling.file.size()) / double(alone.file.size()));
    std::fflush(stdout);
}

}  // namespace

int run_compact_protocol(const BenchOptions& o) {
    std::vector<fs::path> files;
    FILE* out = nullptr;
    if (!list_inputs(o, files, out)) return 1;
    Writer writer(out);
    char dir_template[] = "/tmp/vqtex_compact_XXXXXX";
    if (!::mkdtemp(dir_template)) {
        std::fprintf(stderr, "vqtex-bench: error: cannot make a temporary folder\n");
        return 1;
    }
    const fs::path scratch(dir_template);
    std::vector<uint64_t> targets = o.target_sizes.empty() ? kDefaultTargets : o.target_sizes;
    targets.push_back(0);  // the default
    for (const fs::path& path : files) {
        const std::string name = path.filename().string();
        LoadedImage li = load_image(path.string());
        const Image input = crop(li, 0, 0, li.width, li.height);
        if (input.width <= 256 && input.height <= 256) {
            run_tiling(writer, name, input, scratch, o.seed);
            continue;
        }
        std::vector<Image> sheet_outputs{input};
        Image ceiling;
        Image in_copy = input;
        if (synthesise(in_copy, input.width, input.height, o.seed, ceiling))
            add_row(writer, name, "ceiling:synth-from-input", -1, "", nullptr, 0, ceiling, input, o.seed);
        if (o.compact_parts) {
            vqtex::Image whole(input.width, input.height, input.channels);
            whole.pixels = input.pixels;
            for (int side : {256, 362, 512}) {
                if (side > std::min(input.width, input.height)) continue;
                const std::array<int, 2> at = vqtex::representative_place(whole, side);
                Image part = crop(li, uint32_t(at[0]), uint32_t(at[1]), uint32_t(side), uint32_t(side));
                Image from_part;
                if (synthesise(part, input.width, input.height, o.seed, from_part))
                    add_row(writer, name, "ceiling:part-" + std::to_string(side), -1, "", nullptr, 0, from_part,
                            input, o.seed);
            }
        }
        if (o.compact_inverse) {
            vqtex::Image whole(input.width, input.height, input.channels);
            whole.pixels = input.pixels;
            for (int side : {256, 360, 512}) {
                if (side > std::min(input.width, input.height) / 2) continue;
                vqtex::InverseSynthesisOptions io;
                io.side = side;
                io.seed = o.seed;
                const vqtex::Image t = vqtex::inverse_synthesis(whole, io);
                Image compaction{t.width, t.height, t.channels, t.pixels};
                Image from_compaction;
                if (synthesise(compaction, input.width, input.height, o.seed, from_compaction, true))
                    add_row(writer, name, "ceiling:inverse-" + std::to_string(side), -1, "", nullptr, 0,
                            from_compaction, input, o.seed);
                if (!o.sheets.empty()) {
                    fs::create_directories(o.sheets);
                    write_sheet(fs::path(o.sheets) / ("compact_" + path.stem().string() + "_inverse" + std::to_string(side) + ".png"),
                                std::vector<Image>{input, from_compaction, compaction});
                }
            }
        }
        for (uint64_t target : targets) {
            const int q = int(target);
            const std::string setting = target ? "--target-size " + std::to_string(target) : "default";
            const Encoded v = encode_public(input, target, scratch);
            Image v_out = v.ok ? decode_file(v.file, input.width, input.height, o.seed) : Image{};
            add_row(writer, name, "vqtex", q, setting, &v, v.file.size(), v_out, input, o.seed);
            const Encoded c = encode_crop_rule(input, target, scratch);
            Image c_out = c.ok ? decode_file(c.file, input.width, input.height, o.seed) : Image{};
            add_row(writer, name, "vqtex-crop", q, setting, &c, c.file.size(), c_out, input, o.seed);
            Image a_out;
            if (!o.no_peers && v.ok) {
                std::vector<PeerResult> peers = run_budgeted_peers(input, v.file.size(), scratch.string(), {"avif"});
                if (!peers.empty() && peers[0].fits && synthesise(peers[0].decoded, input.width, input.height, o.seed, a_out))
                    add_row(writer, name, "avif+synth", q, peers[0].setting, nullptr, peers[0].bytes, a_out, input,
                            o.seed);
                else
                    add_row(writer, name, "avif+synth", q, "no fit", nullptr, 0, Image{}, input, o.seed);
            }
            std::printf("%s %s: vqtex %zu bytes (%.2f s), crop rule %zu bytes (%.2f s)\n", name.c_str(),
                        setting.c_str(), v.file.size(), v.seconds, c.file.size(), c.seconds);
            std::fflush(stdout);
            if (!o.sheets.empty()) {
                fs::create_directories(o.sheets);
                std::vector<Image> panels{input, v_out, c_out, a_out, ceiling};
                write_sheet(fs::path(o.sheets) / ("compact_" + path.stem().string() + "_" +
                                                  (target ? std::to_string(target) : std::string("default")) + ".png"),
                            panels);
            }
        }
    }
    if (out) std::fclose(out);
    std::error_code ec;
    fs::remove_all(scratch, ec);
    summarise(writer.rows);
    return 0;
}

}  // namespace vqtex_tools
