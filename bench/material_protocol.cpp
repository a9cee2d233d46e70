// vqtex-bench's materials protocol (see material_protocol.hpp).
#include "material_protocol.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "bench_images.hpp"
#include "bench_rows.hpp"
#include "contact_sheet.hpp"
#include "image_io.hpp"
#include "material_rows.hpp"
#include "material_set.hpp"
#include "material_stats.hpp"
#include "material_summary.hpp"
#include "measured_run.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

// The byte targets of the whole set when --target-sizes does not give
// them: from a sixth of the default quality's budget for three 256x256
// maps (16 KB each) to above it. At 1024x1024 (256 KB a map at the
// default) all are small files, where the maps' shares decide what each
// keeps.
const std::vector<uint64_t> kDefaultTargets{8000, 16000, 32000, 64000};

// `img` with low..high mapped to 0..255 (for a contact sheet only).
Image stretched(Image img, int low, int high) {
    if (high <= low) return img;
    for (uint8_t& v : img.pixels)
        v = uint8_t(std::clamp((int(v) - low) * 255 / (high - low), 0, 255));
    return img;
}

const char* kind_name(vqtex_map_kind kind) {
    return kind == VQTEX_MAP_COLOUR ? "colour" : kind == VQTEX_MAP_NORMAL ? "normal" : "data";
}

// An encoded file, or why there is none, with the encode's wall time and
// the memory it added.
struct Coded {
    std::vector<uint8_t> file;
    std::string status = "ok";  // ok, no-fit (the target is too small), failed
    double seconds = 0;
    long peak_kib = 0;
};

// Runs an encode in a forked child, like every vqtex encode of the bench
// (measured_run.hpp); the child hands back the file, or its status, through
// files in `scratch`.
Coded encode_measured(const std::function<vqtex_status(uint8_t**, size_t*, vqtex_error*)>& encode,
                      const fs::path& scratch, const std::string& what) {
    const std::string file = (scratch / "material.vqt").string(), status = (scratch / "material.status").string();
    std::error_code ec;
    fs::remove(file, ec);
    fs::remove(status, ec);
    Coded c;
    const bool ok = measured([&] {
        uint8_t* data = nullptr;
        size_t size = 0;
        vqtex_error err{};
        const vqtex_status st = encode(&data, &size, &err);
        if (st != VQTEX_OK) {
            const int32_t code = st;
            write_all(status, reinterpret_cast<const uint8_t*>(&code), sizeof code);
            std::fprintf(stderr, "vqtex-bench: %s: %s: %s\n", st == VQTEX_ERROR_LIMIT_EXCEEDED ? "note" : "error",
                         what.c_str(), err.detail);
            return false;
        }
        const vqtex_cpp::Buffer owned(data, size);
        return write_all(file, owned.data(), owned.size());
    }, c.peak_kib, c.seconds);
    if (ok) {
        c.file = read_all(file);
        return c;
    }
    const std::vector<uint8_t> code = read_all(status);
    int32_t st = VQTEX_ERROR_INTERNAL;
    if (code.size() == sizeof st) std::copy(code.begin(), code.end(), reinterpret_cast<uint8_t*>(&st));
    c.status = st == VQTEX_ERROR_LIMIT_EXCEEDED ? "no-fit" : "failed";
    return c;
}

// A file's decoded maps, in the file's order, with the decode's wall time
// and the memory it added.
struct Decoded {
    std::vector<Image> maps;
    bool ok = false;
    double seconds = 0;
    long peak_kib = 0;
};

// vqtex_decode_maps at side x side with `seed`, in a forked child that
// writes each map's pixels and a list of their channels into `scratch`.
// The maps come in the order of `names`, found by name; with no names, in
// the file's order (a file that is not a set names its one map "texture").
Decoded decode_measured(const std::vector<uint8_t>& file, int side, uint64_t seed, const fs::path& scratch,
                        const std::vector<std::string>& names, const std::string& what) {
    const std::string info = (scratch / "maps.info").string();
    auto raw = [&](std::size_t i) { return (scratch / ("map" + std::to_string(i) + ".raw")).string(); };
    Decoded d;
    if (!measured([&] {
            vqtex_decode_params dp;
            vqtex_decode_params_init(&dp);
            dp.width = dp.height = uint32_t(side);
            dp.seed = seed;
            dp.threads = 1;  // the bench times vqtex on one thread everywhere
            try {
                const std::vector<vqtex_cpp::Map> maps = vqtex_cpp::decode_maps(dp, file.data(), file.size());
                std::vector<const vqtex_cpp::Map*> order;
                for (const std::string& name : names) {
                    const auto it = std::find_if(maps.begin(), maps.end(),
                                                 [&](const vqtex_cpp::Map& m) { return m.name == name; });
                    if (it == maps.end()) {
                        std::fprintf(stderr, "vqtex-bench: error: %s: no map %s in the file\n", what.c_str(),
                                     name.c_str());
                        return false;
                    }
                    order.push_back(&*it);
                }
                if (names.empty())
                    for (const vqtex_cpp::Map& m : maps) order.push_back(&m);
                std::vector<uint32_t> channels;
                for (std::size_t i = 0; i < order.size(); ++i) {
                    // The corpus's maps are 8-bit; a map of more bits
                    // would need metrics of its own.
                    if (order[i]->bits != 8) {
                        std::fprintf(stderr, "vqtex-bench: error: %s: map %s has %u bits\n", what.c_str(),
                                     order[i]->name.c_str(), order[i]->bits);
                        return false;
                    }
                    const vqtex_image& im = order[i]->image.get();
                    channels.push_back(im.channels);
                    if (!write_all(raw(i), im.pixels, order[i]->image.size_bytes())) return false;
                }
                return write_all(info, reinterpret_cast<const uint8_t*>(channels.data()),
                                 channels.size() * sizeof(uint32_t));
            } catch (const std::exception& e) {
                std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", what.c_str(), e.what());
                return false;
            }
        }, d.peak_kib, d.seconds))
        return d;
    const std::vector<uint8_t> channels = read_all(info);
    for (std::size_t i = 0; i < channels.size() / sizeof(uint32_t); ++i) {
        uint32_t c = 0;
        std::copy_n(channels.begin() + std::ptrdiff_t(i * sizeof c), sizeof c, reinterpret_cast<uint8_t*>(&c));
        Image im{side, side, int(c), read_all(raw(i))};
        if (im.pixels.size() != std::size_t(side) * side * c) return d;
        d.maps.push_back(std::move(im));
    }
    d.ok = true;
    return d;
}

// One rate point: a preset for each map (the default quality), or a byte
// target for the whole set.
struct RatePoint {
    int quality = -1;
    uint64_t target = 0;
    std::string setting() const {
        return target ? "--target-size " + std::to_string(target) : "-q " + std::to_string(quality);
    }
    std::string label() const { return target ? "t" + std::to_string(target) : "q" + std::to_string(quality); }
};

class SetRun {
public:
    SetRun(const BenchOptions& o, MaterialWriter& writer, const fs::path& scratch, MaterialSet& set)
        : o_(o), writer_(writer), scratch_(scratch), set_(set) {}

    // The rows of one rate point, and its contact sheet. False when an
    // encode or decode failed.
    bool run(const RatePoint& rate);

private:
    // The maps a mode decoded (empty where a map has none) and its rows'
    // common fields.
    struct Mode {
        std::string name;
        std::vector<Image> outputs;
        std::vector<MaterialRow> rows;  // one per map, scores still empty
    };
    MaterialRow base_row(const RatePoint& rate, const std::string& mode, std::size_t map) const;
    void add_map_row(MaterialRow r, const Image* output, std::size_t map);
    void add_pair_rows(const Mode& mode, const RatePoint& rate);
    void write_sheet_of(const RatePoint& rate, const Mode& set_mode, const Mode& separate);
    int output_side() const {
        return o_.material_output ? int(o_.material_output) : set_.maps.front().image.width;
    }

    const BenchOptions& o_;
    MaterialWriter& writer_;
    const fs::path& scratch_;
    MaterialSet& set_;
};

MaterialRow SetRun::base_row(const RatePoint& rate, const std::string& mode, std::size_t map) const {
    MaterialRow r;
    r.set = set_.name;
    r.mode = mode;
    r.map = set_.maps[map].name;
    r.kind = kind_name(set_.maps[map].kind);
    r.quality = rate.quality;
    r.target_size = rate.target;
    r.setting = rate.setting();
    r.side = set_.maps[map].image.width;
    r.output_side = output_side();
    return r;
}

void SetRun::add_map_row(MaterialRow r, const Image* output, std::size_t map) {
    if (o_.no_times) r.encode_s = r.decode_s = 0, r.encode_peak_kib = r.decode_peak_kib = 0;
    if (output && r.status == "ok") {
        const ExampleMap& ex = set_.maps[map];
        // No held-out crop here: the example map is both the reference
        // and the exemplar, so the scores say how far the output is from
        // a new sample of its own example.
        r.scores = score_everything(*output, ex.image, ex.image, o_.seed);
        r.scored = true;
        if (ex.kind == VQTEX_MAP_NORMAL) {
            const Shading s = shading(*output);
            r.shaded = true;
            r.nl_mean = s.mean, r.nl_sd = s.sd, r.off_unit = s.off_unit;
            r.nl_mean_example = set_.shading.mean, r.nl_sd_example = set_.shading.sd;
            r.off_unit_example = set_.shading.off_unit;
            r.nl_wasserstein = wasserstein_1d(s.sorted, set_.shading.sorted);
        }
    }
    writer_.add(r);
}

void SetRun::add_pair_rows(const Mode& mode, const RatePoint& rate) {
    std::vector<std::vector<double>> luma(mode.outputs.size());
    for (std::size_t i = 0; i < mode.outputs.size(); ++i)
        if (!mode.outputs[i].pixels.empty()) luma[i] = luminance(mode.outputs[i]);
    for (std::size_t i = 0; i < set_.maps.size(); ++i)
        for (std::size_t j = i + 1; j < set_.maps.size(); ++j) {
            if (luma[i].empty() || luma[j].empty()) continue;
            MaterialRow r = base_row(rate, mode.name, i);
            r.map = set_.maps[i].name + "~" + set_.maps[j].name;
            r.kind = "pair";
            r.side = set_.maps[i].image.width;
            // The pair's bytes: the set's file, or both files alone.
            r.bytes = mode.rows[i].bytes + mode.rows[j].bytes;
            r.file_bytes = mode.name == "set" ? mode.rows[i].file_bytes
                                              : mode.rows[i].file_bytes + mode.rows[j].file_bytes;
            r.paired = true;
            r.corr = pearson(luma[i], luma[j]);
            r.corr_example = pearson(set_.maps[i].luma, set_.maps[j].luma);
            writer_.add(r);
        }
}

void SetRun::write_sheet_of(const RatePoint& rate, const Mode& set_mode, const Mode& separate) {
    // A row per map: example | the set's output | the map stored alone;
    // then the albedo lit by the normal map, each column's own pair: the
    // set's shading follows its albedo, the separate files' does not. A
    // data map's row is stretched to the full range (the same stretch for
    // its three panels, so they still compare): gloss and masks often use
    // a narrow range that would show as black.
    std::vector<std::vector<Image>> grid;
    for (std::size_t i = 0; i < set_.maps.size(); ++i) {
        std::vector<Image> row{set_.maps[i].image, set_mode.outputs[i], separate.outputs[i]};
        if (set_.maps[i].kind == VQTEX_MAP_DATA) {
            const auto [low, high] = std::minmax_element(set_.maps[i].image.pixels.begin(),
                                                         set_.maps[i].image.pixels.end());
            for (Image& im : row) im = stretched(im, *low, *high);
        }
        grid.push_back(std::move(row));
    }
    if (set_.colour >= 0 && set_.normal >= 0) {
        const auto c = std::size_t(set_.colour), n = std::size_t(set_.normal);
        auto lit_of = [&](const Mode& m) {
            return m.outputs[c].pixels.empty() || m.outputs[n].pixels.empty() ? Image{}
                                                                              : lit(m.outputs[c], m.outputs[n]);
        };
        grid.push_back({lit(set_.maps[c].image, set_.maps[n].image), lit_of(set_mode), lit_of(separate)});
    }
    fs::create_directories(o_.sheets);
    write_sheet(fs::path(o_.sheets) / ("materials_" + set_.name + "_" + rate.label() + ".png"), grid);
}

bool SetRun::run(const RatePoint& rate) {
    const std::size_t count = set_.maps.size();
    const int side = output_side();
    std::vector<vqtex_map> maps;
    for (ExampleMap& m : set_.maps) maps.push_back(vqtex_map{m.name.c_str(), m.kind, 0, view(m.image), nullptr});
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    if (rate.target)
        ep.target_size = rate.target;
    else
        ep.quality = uint32_t(rate.quality);
    ep.threads = 1;
    const std::string what = set_.name + " " + rate.setting();
    bool ok = true;

    // The set: one file, one synthesis.
    Mode set_mode{"set", std::vector<Image>(count), {}};
    const Coded set_file = encode_measured(
        [&](uint8_t** data, size_t* size, vqtex_error* err) {
            return vqtex_encode_maps(&ep, maps.data(), uint32_t(count), data, size, nullptr, err);
        },
        scratch_, what);
    for (std::size_t i = 0; i < count; ++i) {
        MaterialRow r = base_row(rate, "set", i);
        r.status = set_file.status;
        r.file_bytes = set_file.file.size();
        r.encode_s = set_file.seconds, r.encode_peak_kib = set_file.peak_kib;
        set_mode.rows.push_back(r);
    }
    if (set_file.status != "ok") {
        // Without a set file there are no shares to give the maps alone.
        for (std::size_t i = 0; i < count; ++i) add_map_row(set_mode.rows[i], nullptr, i);
        return set_file.status == "no-fit";
    }
    std::vector<std::size_t> shares;
    try {
        shares = shares_of(set_file.file, set_);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", what.c_str(), e.what());
        for (std::size_t i = 0; i < count; ++i) {
            set_mode.rows[i].status = "failed";
            add_map_row(set_mode.rows[i], nullptr, i);
        }
        return false;
    }
    std::vector<std::string> names;
    for (const ExampleMap& m : set_.maps) names.push_back(m.name);
    const Decoded set_decoded = decode_measured(set_file.file, side, o_.seed, scratch_, names, what);
    for (std::size_t i = 0; i < count; ++i) {
        MaterialRow& r = set_mode.rows[i];
        r.bytes = shares[i];
        r.decode_s = set_decoded.seconds, r.decode_peak_kib = set_decoded.peak_kib;
        if (set_decoded.ok && set_decoded.maps.size() == count)
            set_mode.outputs[i] = set_decoded.maps[i];
        else
            r.status = "failed", ok = false;
    }

    // Each map alone at the bytes the set gave it, decoded with the same
    // seed: the colour map as a plain texture (vqtex_encode), a normal or
    // data map as a set of one, the only way to store one.
    Mode separate{"separate", std::vector<Image>(count), {}};
    for (std::size_t i = 0; i < count; ++i) {
        MaterialRow r = base_row(rate, "separate", i);
        vqtex_encode_params alone = ep;
        alone.quality = VQTEX_QUALITY_DEFAULT;
        alone.target_size = shares[i];
        r.setting = "--target-size " + std::to_string(shares[i]) + " (its share of " + rate.setting() + ")";
        const std::string what_alone = set_.name + "/" + set_.maps[i].name + " alone at " + std::to_string(shares[i]);
        const Coded file = encode_measured(
            [&](uint8_t** data, size_t* size, vqtex_error* err) {
                if (set_.maps[i].kind == VQTEX_MAP_COLOUR)
                    return vqtex_encode(&alone, &maps[i].image, data, size, nullptr, err);
                return vqtex_encode_maps(&alone, &maps[i], 1, data, size, nullptr, err);
            },
            scratch_, what_alone);
        r.status = file.status;
        r.bytes = r.file_bytes = file.file.size();
        r.encode_s = file.seconds, r.encode_peak_kib = file.peak_kib;
        if (file.status == "ok") {
            const Decoded d = decode_measured(file.file, side, o_.seed, scratch_, {}, what_alone);
            r.decode_s = d.seconds, r.decode_peak_kib = d.peak_kib;
            if (d.ok && d.maps.size() == 1)
                separate.outputs[i] = d.maps[0];
            else
                r.status = "failed";
        }
        if (r.status == "failed") ok = false;
        separate.rows.push_back(r);
    }

    for (Mode* mode : {&set_mode, &separate}) {
        for (std::size_t i = 0; i < count; ++i)
            add_map_row(mode->rows[i], mode->outputs[i].pixels.empty() ? nullptr : &mode->outputs[i], i);
        add_pair_rows(*mode, rate);
    }
    if (!o_.sheets.empty()) write_sheet_of(rate, set_mode, separate);
    return ok;
}

}  // namespace

int run_material_protocol(const BenchOptions& o) {
    std::vector<fs::path> folders;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(o.folder, ec))
        if (e.is_directory() &&
            (o.sets.empty() || std::find(o.sets.begin(), o.sets.end(), e.path().filename().string()) != o.sets.end()))
            folders.push_back(e.path());
    std::sort(folders.begin(), folders.end());
    if (o.limit && folders.size() > o.limit) folders.resize(o.limit);
    if (folders.empty()) {
        std::fprintf(stderr, "vqtex-bench: error: no material set (a folder of PNG maps) in %s\n", o.folder.c_str());
        return 1;
    }
    FILE* out = nullptr;
    if (!o.csv.empty() && !(out = std::fopen(o.csv.c_str(), "w"))) {
        std::fprintf(stderr, "vqtex-bench: error: cannot write %s\n", o.csv.c_str());
        return 1;
    }
    MaterialWriter writer(out);
    const fs::path scratch = fs::temp_directory_path() / ("vqtex_bench_" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    std::vector<RatePoint> rates{{VQTEX_QUALITY_DEFAULT, 0}};
    for (uint64_t target : o.target_sizes.empty() ? kDefaultTargets : o.target_sizes)
        if (target) rates.push_back({-1, target});  // 0: the default quality alone
    int status = 0;
    int sides[2] = {0, 0};  // the maps' and the outputs' side, for the summary
    for (const fs::path& folder : folders) {
        MaterialSet set;
        try {
            set = load_set(folder, o.material_side);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "vqtex-bench: error: %s\n", e.what());
            status = 1;
            continue;
        }
        if (set.maps.empty()) continue;  // a folder of something else
        sides[0] = set.maps[0].image.width;
        sides[1] = o.material_output ? int(o.material_output) : sides[0];
        SetRun run(o, writer, scratch, set);
        for (const RatePoint& rate : rates) {
            if (!run.run(rate)) status = 1;
            std::fprintf(stderr, "vqtex-bench: %s %s done\n", set.name.c_str(), rate.setting().c_str());
        }
    }
    fs::remove_all(scratch, ec);
    if (out) std::fclose(out);
    print_material_summary(writer.rows, sides[0], sides[1], o.seed);
    return status;
}

}  // namespace vqtex_tools
