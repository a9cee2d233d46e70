// vqtex-bench - rate-quality benchmark of the codec against a held-out crop
// (docs/METRICS.md). Each photograph is cut into an exemplar crop (what the
// encoders see) and a disjoint held-out crop of the same texture; every
// output is scored against the held-out crop, beside the floor (the
// exemplar itself against the held-out crop).
//
// For each vqtex rate, every peer (JPEG, WebP, AVIF, JPEG XL) encodes the
// same exemplar at or under the same byte budget; ASTC rows give its fixed
// rates. Two protocols:
//   same:  outputs as large as the exemplar (vqtex decode vs each peer's decode);
//   large: outputs 2x2 the exemplar's area: vqtex decode, each peer's decode
//          tiled, and the strongest simple alternatives: the peer's decode
//          synthesised to the output size by vqtex's own engine (PEER+synth)
//          and by G'MIC's syntexturize_matchpatch (PEER+gmic). Its summary
//          ends with issue 17's acceptance test: vqtex against the best
//          PEER+synth row at every rate.
// Plus the ceilings: vqtex's synthesis from the exemplar itself, and in the
// large protocol G'MIC's as well.
// A third protocol, chosen with --protocols, compares synthesisers rather
// than codecs:
//   synth: vqtex's engine and G'MIC's syntexturize_matchpatch each
//          synthesise 2x2 the exemplar's area from the lossless exemplar.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_peers.hpp"
#include "cli_common.hpp"
#include "format/atlas_file.hpp"
#include "image_io.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

namespace fs = std::filesystem;
using namespace vqtex_tools;
using vqtex_metrics::Image;

namespace {

Image crop(const LoadedImage& img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
    Image out{int(w), int(h), int(img.channels), {}};
    out.pixels.resize(std::size_t(w) * h * img.channels);
    for (uint32_t y = 0; y < h; ++y)
        std::copy_n(img.pixels.data() + ((std::size_t(y0 + y) * img.width + x0) * img.channels),
                    std::size_t(w) * img.channels, out.pixels.data() + std::size_t(y) * w * img.channels);
    return out;
}

Image tiled(const Image& img, int w, int h) {
    Image out{w, h, img.channels, {}};
    out.pixels.resize(std::size_t(w) * h * img.channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            std::copy_n(img.pixels.data() + (std::size_t(y % img.height) * img.width + x % img.width) * img.channels,
                        img.channels, out.pixels.data() + (std::size_t(y) * w + x) * img.channels);
    return out;
}

// Takes the library's image (and releases it).
Image from_c(vqtex_image& c) {
    const vqtex_cpp::Image owned(std::exchange(c, vqtex_image{}));
    return Image{int(owned.width()), int(owned.height()), int(owned.channels()),
                 std::vector<uint8_t>(owned.data(), owned.data() + owned.size_bytes())};
}

vqtex_image view(Image& img) { return {uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data()}; }

// The atlas a format v3 file stores, as its decoder sees it (for the large
// protocol's contact sheets: what the engine synthesises from). Empty for a
// file of another version, or if the file does not read.
Image decoded_atlas(const std::vector<uint8_t>& file) {
    if (!vqtex::is_atlas_file(file.data(), file.size())) return {};
    try {
        constexpr std::size_t kMemoryLimit = std::size_t(1) << 30;  // the decoder's default
        vqtex::AtlasFile decoded = vqtex::decode_atlas_file(file.data(), file.size(), kMemoryLimit);
        return Image{decoded.atlas.width, decoded.atlas.height, decoded.atlas.channels,
                     std::move(decoded.atlas.pixels)};
    } catch (const std::exception&) {
        return {};
    }
}

// Synthesis from an image with vqtex's engine (full codebooks).
bool synthesise(Image& example, int w, int h, uint64_t seed, Image& out) {
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.width = uint32_t(w);
    p.height = uint32_t(h);
    p.seed = seed;
    p.threads = 1;
    vqtex_image in = view(example), result{};
    vqtex_error err{};
    if (vqtex_synthesize(&p, &in, &result, nullptr, &err) != VQTEX_OK) return false;
    out = from_c(result);
    return true;
}

// A contact sheet: a grid of panels, 4 px gaps, every cell as wide as the
// widest panel and each row as tall as its tallest, so that outputs of
// different sizes line up in columns. An empty Image leaves its cell white,
// which keeps a missing output from shifting the others out of place.
void write_sheet(const fs::path& path, const std::vector<std::vector<Image>>& grid) {
    const int gap = 4;
    int cell_w = 0, columns = 0, sheet_h = 0;
    std::vector<int> row_h(grid.size(), 0);
    for (std::size_t r = 0; r < grid.size(); ++r) {
        columns = std::max(columns, int(grid[r].size()));
        for (const Image& im : grid[r]) cell_w = std::max(cell_w, im.width), row_h[r] = std::max(row_h[r], im.height);
        sheet_h += row_h[r] + (r ? gap : 0);
    }
    const int sheet_w = columns * (cell_w + gap) - gap;
    if (sheet_w <= 0 || sheet_h <= 0) return;
    std::vector<uint8_t> sheet(std::size_t(sheet_w) * sheet_h * 3, 255);
    int top = 0;
    for (std::size_t r = 0; r < grid.size(); ++r) {
        for (std::size_t i = 0; i < grid[r].size(); ++i) {
            const Image& im = grid[r][i];
            const int left = int(i) * (cell_w + gap);
            for (int y = 0; y < im.height; ++y)
                for (int x = 0; x < im.width; ++x)
                    for (int c = 0; c < 3; ++c)
                        sheet[(std::size_t(top + y) * sheet_w + left + x) * 3 + c] =
                            im.pixels[(std::size_t(y) * im.width + x) * im.channels + std::min(c, im.channels - 1)];
        }
        top += row_h[r] + gap;
    }
    save_image(path.string(), uint32_t(sheet_w), uint32_t(sheet_h), 3, sheet.data());
}

void write_sheet(const fs::path& path, const std::vector<Image>& panels) {
    write_sheet(path, std::vector<std::vector<Image>>{panels});
}

// Both synthesisers of the synth protocol run on one thread: the bench
// times vqtex on one thread everywhere, and G'MIC (OpenMP) gets the same
// through OMP_NUM_THREADS so that the wall times compare like for like.
constexpr uint32_t kSynthThreads = 1;

// FNV-1a over the exemplar's size and pixels: part of a G'MIC cache key, so
// that two corpora with a file of the same name never share an entry.
uint64_t image_hash(const Image& img) {
    uint64_t h = 14695981039346656037ULL;
    auto mix = [&](uint8_t b) { h = (h ^ b) * 1099511628211ULL; };
    for (int v : {img.width, img.height, img.channels})
        for (int i = 0; i < 4; ++i) mix(uint8_t(uint32_t(v) >> (8 * i)));
    for (uint8_t b : img.pixels) mix(b);
    return h;
}

long status_kib(const char* field) {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::strlen(field));
    return 0;
}

// Runs `work` in a forked child, so that every encode and decode is measured
// on its own: the peak memory it added (the child's high-water mark minus
// what it inherited) and its wall time. The child reports through files.
bool measured(const std::function<bool()>& work, long& peak_kib, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    std::fflush(nullptr);
    int pipe_fds[2];
    if (::pipe(pipe_fds) != 0) return false;
    const pid_t pid = ::fork();
    if (pid < 0) return false;
    if (pid == 0) {
        ::close(pipe_fds[0]);
        const long base = status_kib("VmRSS:");
        const bool ok = work();
        const long added = status_kib("VmHWM:") - base;
        if (::write(pipe_fds[1], &added, sizeof added) != ssize_t(sizeof added)) ::_exit(2);
        ::_exit(ok ? 0 : 1);
    }
    ::close(pipe_fds[1]);
    long added = 0;
    const bool got = ::read(pipe_fds[0], &added, sizeof added) == ssize_t(sizeof added);
    ::close(pipe_fds[0]);
    int status = 0;
    if (::waitpid(pid, &status, 0) < 0) return false;
    peak_kib = got ? added : 0;
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::vector<uint8_t> read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

bool write_all(const std::string& path, const uint8_t* data, std::size_t n) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(n));
    return bool(f);
}

struct Row {
    std::string texture, protocol, codec, setting;
    int quality = -1;
    std::size_t bytes = 0;
    double bpp_exemplar = 0, bpp_output = 0, encode_s = 0, decode_s = 0;
    long encode_peak_kib = 0, decode_peak_kib = 0;
    double wall_s = 0;  // synth protocol: whole synthesis; summary only, not a CSV column
    std::string status = "ok";  // ok, missing, no-fit, failed
    vqtex_metrics::Scores scores{};
};

class Writer {
public:
    explicit Writer(FILE* f) : f_(f) {
        if (f_)
            std::fputs("texture,protocol,codec,quality,setting,status,bytes,bpp_exemplar,bpp_output,swd,swd_floor,"
                       "colour_de,colour_de_floor,colour_dist,colour_dist_floor,completeness,completeness_floor,"
                       "coherence,coherence_floor,copy_exact,copy_exact_floor,copy_neighbour,copy_neighbour_floor,"
                       "seam_ratio,seam_ratio_floor,straight_seam,straight_seam_floor,encode_s,decode_s,"
                       "encode_peak_kib,decode_peak_kib,hard_to_rank\n",
                       f_);
    }
    // Textures whose exemplar already differs a lot from the held-out crop
    // (large features, e.g. clouds) cannot rank codecs reliably.
    static bool hard_to_rank(const vqtex_metrics::Scores& floor) {
        return floor.swd.mean > 8.0 || floor.completeness > 15.0;
    }
    void add(const Row& r, const vqtex_metrics::Scores& floor) {
        rows.push_back(r);
        if (!f_) return;
        const auto& s = r.scores;
        std::fprintf(f_, "%s,%s,%s,%d,%s,%s,%zu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%ld,%ld,%d\n",
                     r.texture.c_str(), r.protocol.c_str(), r.codec.c_str(), r.quality, r.setting.c_str(),
                     r.status.c_str(), r.bytes, r.bpp_exemplar, r.bpp_output, s.swd.mean, floor.swd.mean,
                     s.colour.mean_delta_e, floor.colour.mean_delta_e, s.colour.distribution,
                     floor.colour.distribution, s.completeness, floor.completeness, s.coherence, floor.coherence,
                     s.copy.exact_share, floor.copy.exact_share, s.copy.neighbour_coherence,
                     floor.copy.neighbour_coherence, s.seam_ratio, floor.seam_ratio, s.straight_seam,
                     floor.straight_seam, r.encode_s, r.decode_s,
                     r.encode_peak_kib, r.decode_peak_kib, hard_to_rank(floor) ? 1 : 0);
        std::fflush(f_);
    }
    std::vector<Row> rows;

private:
    FILE* f_;
};

// vqtex's synthesis for the synth protocol, in a forked child like every
// vqtex encode and decode (so that its peak memory is its own); the child
// hands back the pixels and vqtex_synth_stats through files in `scratch`.
bool synthesise_measured(const Image& example, int w, int h, uint64_t seed, const fs::path& scratch, Image& out,
                         vqtex_synth_stats& stats, long& peak_kib, double& wall_s) {
    const std::string raw = (scratch / "synth.raw").string(), stats_file = (scratch / "synth.stats").string();
    Image ex = example;
    if (!measured([&] {
            vqtex_synth_params p;
            vqtex_synth_params_init(&p);
            p.width = uint32_t(w);
            p.height = uint32_t(h);
            p.seed = seed;
            p.threads = kSynthThreads;
            vqtex_image in = view(ex), result{};
            vqtex_synth_stats st{};
            vqtex_error err{};
            if (vqtex_synthesize(&p, &in, &result, &st, &err) != VQTEX_OK) {
                std::fprintf(stderr, "vqtex-bench: error: synthesis: %s\n", err.detail);
                return false;
            }
            const bool ok =
                write_all(raw, result.pixels, std::size_t(result.width) * result.height * result.channels) &&
                write_all(stats_file, reinterpret_cast<const uint8_t*>(&st), sizeof st);
            vqtex_image_free(&result);
            return ok;
        }, peak_kib, wall_s))
        return false;
    const std::vector<uint8_t> st = read_all(stats_file);
    if (st.size() != sizeof stats) return false;
    std::memcpy(&stats, st.data(), sizeof stats);
    out = Image{w, h, example.channels, read_all(raw)};
    return out.pixels.size() == std::size_t(w) * h * example.channels;
}

// G'MIC's syntexturize_matchpatch on the exemplar, or its cached output.
struct GmicResult {
    std::string status = "ok";  // ok, missing, failed
    Image output;
    double seconds = 0;  // the whole gmic command, wall time
    long peak_kib = 0;
    bool cached = false;
};

// The CSV setting of a row G'MIC made (without the cache mark).
std::string gmic_setting(uint64_t seed) {
    return "syntexturize_matchpatch srand=" + std::to_string(seed & 0x7fffffffULL) +
           " OMP_NUM_THREADS=" + std::to_string(kSynthThreads);
}

// G'MIC seeds its generator from the clock unless told; `srand` makes a run
// repeatable, which is what lets its outputs be cached by seed. A cache
// entry is NAME_WxH_sSEED_HASH.png plus a .txt holding the seconds and peak
// KiB of the run that made it, so cached rows still report G'MIC's cost.
GmicResult run_gmic(const Image& exemplar, int w, int h, uint64_t seed, const std::string& stem,
                    const fs::path& scratch, const std::string& cache, bool available) {
    GmicResult g;
    char key[64];
    std::snprintf(key, sizeof key, "_%dx%d_s%llu_%08llx", w, h, static_cast<unsigned long long>(seed),
                  static_cast<unsigned long long>(image_hash(exemplar) & 0xffffffffULL));
    const fs::path cached_png = cache.empty() ? fs::path() : fs::path(cache) / (stem + key + ".png");
    const fs::path cached_txt = cache.empty() ? fs::path() : fs::path(cache) / (stem + key + ".txt");
    auto load = [&](const fs::path& path) {
        try {
            LoadedImage li = load_image(path.string());
            if (int(li.width) != w || int(li.height) != h) return false;
            g.output = Image{w, h, int(li.channels), std::move(li.pixels)};
            return true;
        } catch (const std::exception&) {
            return false;
        }
    };
    if (!cache.empty() && fs::exists(cached_png) && fs::exists(cached_txt)) {
        std::ifstream t(cached_txt);
        if (t >> g.seconds >> g.peak_kib && load(cached_png)) {
            g.cached = true;
            return g;
        }
    }
    if (!available) {
        g.status = "missing";
        return g;
    }
    const std::string in = (scratch / "gmic_in.png").string(), out = (scratch / "gmic_out.png").string();
    save_image(in, uint32_t(exemplar.width), uint32_t(exemplar.height), uint32_t(exemplar.channels),
               exemplar.pixels.data());
    std::error_code ec;
    fs::remove(out, ec);
    // srand takes a 32-bit integer.
    const std::string command = "OMP_NUM_THREADS=" + std::to_string(kSynthThreads) + " gmic -v -1 srand " +
                                std::to_string(seed & 0x7fffffffULL) + " " + in + " syntexturize_matchpatch " +
                                std::to_string(w) + "," + std::to_string(h) + " o " + out;
    if (run_measured(command, &g.peak_kib, &g.seconds) != 0 || !load(out)) {
        g.status = "failed";
        return g;
    }
    if (!cache.empty()) {
        fs::create_directories(cache);
        save_image(cached_png.string(), uint32_t(w), uint32_t(h), uint32_t(g.output.channels),
                   g.output.pixels.data());
        std::ofstream(cached_txt) << g.seconds << " " << g.peak_kib << "\n";
    }
    return g;
}

// The synth protocol's summary: the mean of every score per synthesiser
// over the textures it scored (column n; the floor over all of them), then
// one line per texture with the metrics on which vqtex scores worse than
// G'MIC, so that a developer sees which textures lose and how.
void print_synth_summary(const std::vector<Row>& rows, const std::map<std::string, vqtex_metrics::Scores>& floors) {
    std::map<std::string, std::map<std::string, const Row*>> by_texture;  // texture -> codec -> row
    for (const Row& r : rows)
        if (r.protocol == "synth" && r.status == "ok") by_texture[r.texture][r.codec] = &r;
    const char* codecs[] = {"vqtex", "gmic"};
    struct Mean {
        double swd = 0, de = 0, cdist = 0, compl_ = 0, coh = 0, copy = 0, ncoh = 0, seam = 0, straight = 0,
               analyse = 0, synth = 0, wall = 0;
        int n = 0;
        void add(const vqtex_metrics::Scores& s) {
            swd += s.swd.mean, de += s.colour.mean_delta_e, cdist += s.colour.distribution;
            compl_ += s.completeness, coh += s.coherence, copy += s.copy.exact_share;
            ncoh += s.copy.neighbour_coherence, seam += s.seam_ratio, straight += s.straight_seam;
            ++n;
        }
    };
    std::map<std::string, Mean> means;
    for (const auto& [texture, row] : by_texture) {
        if (auto f = floors.find(texture); f != floors.end()) means["floor"].add(f->second);
        for (const auto& [codec, r] : row) {
            Mean& m = means[codec];
            m.add(r->scores);
            m.analyse += r->encode_s, m.synth += r->decode_s, m.wall += r->wall_s;
        }
    }
    std::printf("\nsynth protocol (%zu textures; threads %u each; lower is better; floor = exemplar vs held-out)\n",
                by_texture.size(), kSynthThreads);
    std::printf("%-6s %3s %7s %7s %7s %7s %7s %6s %6s %7s %7s %8s %8s %8s\n", "codec", "n", "SWD", "dE",
                "colour", "compl", "coher", "copy", "ncopy", "seamR", "strS", "analyse", "synth", "wall");
    for (const char* codec : {"floor", "vqtex", "gmic"}) {
        auto it = means.find(codec);
        if (it == means.end()) continue;
        const Mean& m = it->second;
        const double n = m.n;
        std::printf("%-6s %3d %7.2f %7.2f %7.2f %7.2f %7.2f %6.3f %6.3f %7.2f %7.2f", codec, m.n, m.swd / n,
                    m.de / n, m.cdist / n, m.compl_ / n, m.coh / n, m.copy / n, m.ncoh / n, m.seam / n,
                    m.straight / n);
        if (std::strcmp(codec, "floor") == 0)
            std::printf("\n");
        else
            std::printf(" %8.3f %8.3f %8.3f\n", m.analyse / n, m.synth / n, m.wall / n);
    }
    std::printf("\n%-28s %13s | %-34s | %-34s | %s\n", "", "floor", "vqtex", "gmic", "");
    std::printf("%-28s %6s %6s |", "texture", "compl", "SWD");
    for (int i = 0; i < 2; ++i) std::printf(" %6s %6s %6s %6s %6s |", "compl", "SWD", "coher", "seamR", "strS");
    std::printf(" vqtex worse on\n");
    for (const auto& [texture, row] : by_texture) {
        const auto f = floors.find(texture);
        std::printf("%-28s %6.2f %6.2f |", texture.c_str(), f != floors.end() ? f->second.completeness : 0.0,
                    f != floors.end() ? f->second.swd.mean : 0.0);
        for (const char* codec : codecs) {
            auto it = row.find(codec);
            if (it == row.end()) {
                std::printf(" %34s |", "-");
                continue;
            }
            const auto& s = it->second->scores;
            std::printf(" %6.2f %6.2f %6.2f %6.2f %6.2f |", s.completeness, s.swd.mean, s.coherence, s.seam_ratio,
                        s.straight_seam);
        }
        std::string worse;
        if (row.size() == 2) {
            const auto& v = row.at("vqtex")->scores;
            const auto& g = row.at("gmic")->scores;
            // Tileability (seamR) is left out: vqtex's outputs tile by design,
            // G'MIC's are not meant to.
            const std::pair<const char*, bool> checks[] = {
                {"compl", v.completeness > g.completeness}, {"SWD", v.swd.mean > g.swd.mean},
                {"coher", v.coherence > g.coherence}, {"colour", v.colour.distribution > g.colour.distribution},
                {"strS", v.straight_seam > g.straight_seam}};
            for (const auto& [label, lost] : checks)
                if (lost) worse += (worse.empty() ? "" : " ") + std::string(label);
            if (const auto f2 = floors.find(texture); f2 != floors.end() && Writer::hard_to_rank(f2->second))
                worse += " (hard to rank)";
        }
        std::printf(" %s\n", worse.c_str());
    }
}

// The scores issue 17's acceptance test reads; lower is better for each.
struct AcceptanceMetric {
    const char* label;
    double (*of)(const vqtex_metrics::Scores&);
};
constexpr AcceptanceMetric kAcceptanceMetrics[] = {
    {"compl", [](const vqtex_metrics::Scores& s) { return s.completeness; }},
    {"SWD", [](const vqtex_metrics::Scores& s) { return s.swd.mean; }},
    {"coher", [](const vqtex_metrics::Scores& s) { return s.coherence; }},
};

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// vqtex against one PEER+SYNTHESISER row on one metric, over the textures
// where both scored (a peer that does not fit a texture's budget has no
// row there, so that texture cannot be compared).
struct Paired {
    int n = 0, at_or_below = 0;  // textures compared; those where vqtex <= peer
    double vqtex_mean = 0, peer_mean = 0;
};

Paired pair_up(const std::map<std::string, const Row*>& vqtex, const std::map<std::string, const Row*>& peer,
               const AcceptanceMetric& metric) {
    Paired p;
    for (const auto& [texture, v] : vqtex) {
        const auto it = peer.find(texture);
        if (it == peer.end()) continue;
        const double mine = metric.of(v->scores), theirs = metric.of(it->second->scores);
        p.vqtex_mean += mine, p.peer_mean += theirs, ++p.n;
        if (mine <= theirs) ++p.at_or_below;
    }
    if (p.n) p.vqtex_mean /= p.n, p.peer_mean /= p.n;
    return p;
}

// The large protocol's summary, per rate point: the mean completeness, SWD
// and coherence of vqtex, of every PEER+synth and PEER+gmic row and of the
// ceilings; then vqtex against the best PEER+synth row, issue 17's
// acceptance test ("at every rate point, vqtex's mean completeness, SWD and
// coherence are at or below the best peer + vqtex synthesis row's, and at
// or below it on at least two thirds of the textures"), and, for
// reference, against the best PEER+gmic row.
//
// The best row per metric is the one with the lowest mean among the peers
// that fit the budget on every texture vqtex scored, so that its mean is
// taken over the same textures as vqtex's. A peer that misses some
// textures (typically the hardest ones, at the smallest budgets) would
// otherwise look better by leaving them out: it is not a candidate, but it
// is still compared with vqtex on the textures both scored, with n. When no
// peer covers every texture, the best is taken among those that cover the
// most, and the verdict says "partial".
void print_large_summary(const std::vector<Row>& rows) {
    using ByTexture = std::map<std::string, const Row*>;
    std::map<int, std::map<std::string, ByTexture>> by_rate;  // rate -> codec -> texture -> row
    std::map<std::string, ByTexture> ceilings;                // the same at every rate
    // Why a peer's rows are absent or short at a rate: its status rows
    // ("jpeg no-fit" means no PEER+synth or PEER+gmic row for that texture).
    std::map<int, std::map<std::string, int>> unscored;  // rate -> "codec status" -> textures
    for (const Row& r : rows) {
        if (r.status != "ok" && r.quality >= 0 && (r.protocol == "large" || r.protocol == "same"))
            ++unscored[r.quality][r.codec + " " + r.status];
        if (r.protocol != "large" || r.status != "ok") continue;
        if (r.codec.rfind("ceiling:", 0) == 0)
            ceilings[r.codec][r.texture] = &r;
        else if (r.codec.rfind("vqtex", 0) == 0 || ends_with(r.codec, "+synth") || ends_with(r.codec, "+gmic"))
            by_rate[r.quality][r.codec][r.texture] = &r;
    }
    if (by_rate.empty()) return;
    std::printf(
        "\nlarge protocol: vqtex against peer + synthesis (issue 17; means over the textures each row "
        "scored, n; lower is better)\n");
    for (const auto& [rate, codecs] : by_rate) {
        std::string vqtex_codec;
        for (const auto& [codec, textures] : codecs)
            if (codec.rfind("vqtex", 0) == 0) vqtex_codec = codec;
        if (vqtex_codec.empty()) continue;
        const ByTexture& vqtex = codecs.at(vqtex_codec);
        const int total = int(vqtex.size());
        std::printf("\nrate %d (%d textures)\n%-30s %3s %8s %7s %7s %7s\n", rate, total, "row", "n", "bytes", "compl",
                    "SWD", "coher");
        auto print_means = [&](const std::string& codec, const ByTexture& textures) {
            double bytes = 0, sums[std::size(kAcceptanceMetrics)] = {};
            for (const auto& [texture, r] : textures) {
                bytes += double(r->bytes);
                for (std::size_t m = 0; m < std::size(kAcceptanceMetrics); ++m)
                    sums[m] += kAcceptanceMetrics[m].of(r->scores);
            }
            const double n = double(textures.size());
            std::printf("%-30s %3zu %8.0f %7.2f %7.2f %7.2f%s\n", codec.c_str(), textures.size(), bytes / n,
                        sums[0] / n, sums[1] / n, sums[2] / n,
                        int(textures.size()) < total ? "  (not all textures)" : "");
        };
        print_means(vqtex_codec, vqtex);
        for (const auto& [codec, textures] : ceilings) print_means(codec, textures);
        for (const char* kind : {"+synth", "+gmic"})
            for (const auto& [codec, textures] : codecs)
                if (ends_with(codec, kind)) print_means(codec, textures);
        if (const auto it = unscored.find(rate); it != unscored.end()) {
            std::printf("not scored:");
            for (const auto& [what, count] : it->second) std::printf(" %s on %d;", what.c_str(), count);
            std::printf("\n");
        }

        for (const char* kind : {"+synth", "+gmic"}) {
            const bool acceptance = std::strcmp(kind, "+synth") == 0;
            std::printf("%s vs best peer%s%s\n", vqtex_codec.c_str(), kind,
                        acceptance ? " (acceptance: mean at or below, and at or below on >= 2/3 of the textures)"
                                   : " (for reference)");
            for (const AcceptanceMetric& metric : kAcceptanceMetrics) {
                // Candidates: the peers with the widest coverage (ideally all
                // of vqtex's textures); the best is the lowest mean among them.
                std::string best;
                Paired best_pair;
                std::vector<std::pair<std::string, Paired>> partial;
                int widest = 0;
                for (const auto& [codec, textures] : codecs)
                    if (ends_with(codec, kind)) widest = std::max(widest, pair_up(vqtex, textures, metric).n);
                for (const auto& [codec, textures] : codecs) {
                    if (!ends_with(codec, kind)) continue;
                    const Paired p = pair_up(vqtex, textures, metric);
                    if (p.n == 0) continue;
                    if (p.n == widest && (best.empty() || p.peer_mean < best_pair.peer_mean))
                        best = codec, best_pair = p;
                    if (p.n < total) partial.emplace_back(codec, p);
                }
                if (best.empty()) {
                    std::printf("  %-5s no peer%s row to compare with: n/a\n", metric.label, kind);
                    continue;
                }
                const int needed = (2 * best_pair.n + 2) / 3;  // two thirds, rounded up
                const bool mean_ok = best_pair.vqtex_mean <= best_pair.peer_mean;
                const bool count_ok = best_pair.at_or_below >= needed;
                std::printf("  %-5s %7.2f vs %-14s %7.2f  n=%d: mean %s; at or below on %d of %d (needs %d): %s%s\n",
                            metric.label, best_pair.vqtex_mean, best.c_str(), best_pair.peer_mean, best_pair.n,
                            mean_ok ? "at or below" : "ABOVE", best_pair.at_or_below, best_pair.n, needed,
                            mean_ok && count_ok ? "PASS" : "FAIL", best_pair.n < total ? " (partial)" : "");
                for (const auto& [codec, p] : partial)
                    if (codec != best)
                        std::printf("        partial %-14s %7.2f vs %7.2f  n=%d of %d: at or below on %d\n",
                                    codec.c_str(), p.vqtex_mean, p.peer_mean, p.n, total, p.at_or_below);
            }
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-bench: rate-quality of vqtex and peer codecs against held-out crops (docs/METRICS.md)."};
    std::string folder = "corpus", pattern = ".png", csv;
    std::vector<int> qualities{20, 50, 80};
    uint32_t limit = 0;
    uint64_t seed = 1;
    bool quick = false, no_peers = false, no_times = false;
    std::string sheets, synth_cache;
    std::vector<std::string> protocols{"same", "large"};
    uint32_t synth_size = 0;
    bool atlas = false;
    std::vector<uint64_t> target_sizes;
    app.add_flag("--atlas", atlas, "vqtex rows are format v3 atlas files (vqtex-encode --atlas)");
    app.add_option("--target-sizes", target_sizes,
                   "rate points as byte targets (vqtex-encode --target-size) instead of -q presets; "
                   "the summary's q column then holds the target")
        ->delimiter(',');
    app.add_option("folder", folder, "folder of textures (each cut into exemplar and held-out crops)")
        ->capture_default_str();
    app.add_option("--pattern", pattern, "only files whose name contains this (e.g. _256.png)")->capture_default_str();
    app.add_option("-q,--qualities", qualities, "vqtex quality presets (the rate points)")->capture_default_str();
    app.add_option("--csv", csv, "write every row here");
    app.add_option("--limit", limit, "at most this many textures");
    app.add_option("--seed", seed, "decoding and synthesis seed")->capture_default_str();
    app.add_flag("--no-peers", no_peers, "vqtex only");
    app.add_flag("--quick", quick, "two textures, one rate");
    app.add_flag("--no-times", no_times, "write 0 for times (for baselines reviewed as diffs)");
    app.add_option("--sheets", sheets, "write contact sheets into this folder (same: exemplar | held-out | vqtex | peers; "
                   "large: ... | each peer+synth | each peer+gmic; docs/METRICS.md)");
    app.add_option("--protocols", protocols, "protocols to run, comma-separated: same, large, synth")
        ->delimiter(',')
        ->check(CLI::IsMember({"same", "large", "synth"}))
        ->capture_default_str();
    app.add_option("--synth-size", synth_size, "synth protocol: output side (default: 2x the exemplar's width and height)")
        ->check(CLI::Range(8u, 16384u));
    app.add_option("--synth-cache", synth_cache, "keep G'MIC's outputs here (synth protocol, large protocol's gmic rows), "
                   "by texture, size, seed and input pixels");
    CLI11_PARSE(app, argc, argv);
    if (quick) {
        limit = 2;
        qualities = {VQTEX_QUALITY_DEFAULT};
    }
    auto want = [&](const std::string& protocol) {
        return std::find(protocols.begin(), protocols.end(), protocol) != protocols.end();
    };
    // The rate points (encodes, peers, ASTC) serve only the same and large protocols.
    const bool rates = want("same") || want("large");
    // G'MIC serves the synth protocol and the large protocol's PEER+gmic and
    // ceiling rows; it is optional (its rows then say missing).
    const bool gmic_available = (want("synth") || want("large")) && !no_peers && tool_available("gmic");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder))
        if (e.path().filename().string().find(pattern) != std::string::npos && e.path().extension() == ".png")
            files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (limit && files.size() > limit) files.resize(limit);
    if (files.empty()) {
        std::fprintf(stderr, "vqtex-bench: error: no '%s' PNG files in %s\n", pattern.c_str(), folder.c_str());
        return 1;
    }
    FILE* out = nullptr;
    if (!csv.empty() && !(out = std::fopen(csv.c_str(), "w"))) {
        std::fprintf(stderr, "vqtex-bench: error: cannot write %s\n", csv.c_str());
        return 1;
    }
    Writer writer(out);
    const fs::path scratch = fs::temp_directory_path() / ("vqtex_bench_" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    if (!no_peers && rates)
        for (const char* tool : {"cjpeg", "cwebp", "avifenc", "cjxl", "astcenc"})
            if (!tool_available(tool)) std::fprintf(stderr, "vqtex-bench: note: %s not found: its rows say missing (scripts/setup-bench.sh)\n", tool);
    if ((want("synth") || want("large")) && !no_peers && !gmic_available)
        std::fprintf(stderr, "vqtex-bench: note: gmic not found: its rows (synth, large PEER+gmic) say missing\n");
    std::map<std::string, vqtex_metrics::Scores> floors;  // per texture, for the synth summary

    for (const auto& f : files) {
        LoadedImage img = load_image(f.string());
        const uint32_t w = img.width / 2, h = img.height / 2;
        // Exemplar: top-left quarter; held-out: bottom-right quarter.
        Image exemplar = crop(img, 0, 0, w, h);
        const Image held_out = crop(img, w, h, w, h);
        const vqtex_metrics::Scores floor = vqtex_metrics::floor_scores(held_out, exemplar, seed);
        const std::string name = f.filename().string();
        const std::string stem = fs::path(name).stem().string();
        const double ex_pixels = double(w) * h;
        floors[name] = floor;
        // Contact sheet panels, per rate: exemplar | held-out | vqtex | peers.
        std::map<int, std::vector<Image>> panels;
        auto score = [&](Row r, const Image& output) {
            if (!want(r.protocol)) return;
            if (!sheets.empty() && r.protocol == "same" && r.quality >= 0) {
                auto& p = panels[r.quality];
                if (p.empty()) p = {exemplar, held_out};
                p.push_back(output);
            }
            r.texture = name;
            r.bpp_exemplar = 8.0 * double(r.bytes) / ex_pixels;
            r.bpp_output = 8.0 * double(r.bytes) / (double(output.width) * output.height);
            r.scores = vqtex_metrics::score_all(output, held_out, exemplar, seed);
            writer.add(r, floor);
        };
        // A row G'MIC made (or could not make: missing, failed).
        auto add_gmic_row = [&](Row r, GmicResult& g) {
            r.status = g.status;
            if (g.status == "ok") {
                score(r, g.output);
            } else {
                r.texture = name;
                writer.add(r, floor);
            }
        };
        // What a budgeted peer gives the large protocol's contact sheet:
        // its decode and the two syntheses from it (empty when absent).
        struct PeerSyntheses {
            Image decoded, by_vqtex, by_gmic;
        };
        // A peer's rows: its decode as is, tiled to the larger output, and
        // (budgeted peers) synthesised to it by vqtex's engine and by G'MIC.
        auto add_peer_rows = [&](PeerResult& peer, int quality, bool with_synthesis) {
            PeerSyntheses sheet_panels;
            Row r;
            r.codec = peer.codec;
            r.quality = quality;
            r.setting = peer.setting;
            r.bytes = peer.bytes;
            r.encode_s = no_times ? 0 : peer.encode_s;
            r.decode_s = no_times ? 0 : peer.decode_s;
            r.encode_peak_kib = no_times ? 0 : peer.encode_peak_kib;
            r.decode_peak_kib = no_times ? 0 : peer.decode_peak_kib;
            r.protocol = want("same") ? "same" : "large";
            if (!peer.available || !peer.fits) {
                r.status = !peer.available ? "missing" : with_synthesis ? "no-fit" : "failed";
                r.texture = name;
                writer.add(r, floor);
                return sheet_panels;
            }
            // The decode as it is (exemplar-sized) is a same-protocol row
            // only: r.protocol says "large" above when same is not run, for
            // the status rows, and a large run then also scored the small
            // decode under the peer's name, beside its tiled decode.
            r.protocol = "same";
            score(r, peer.decoded);
            r.protocol = "large";
            score(r, tiled(peer.decoded, int(w) * 2, int(h) * 2));
            if (!with_synthesis || !want("large")) return sheet_panels;
            sheet_panels.decoded = peer.decoded;
            // Both rows keep the peer's bytes, setting and coding times: the
            // synthesis cost is the synth protocol's to measure.
            Row synth_row = r, gmic_row = r;
            if (synthesise(peer.decoded, int(w) * 2, int(h) * 2, seed, sheet_panels.by_vqtex)) {
                synth_row.codec = peer.codec + "+synth";
                score(synth_row, sheet_panels.by_vqtex);
            }
            // Keyed by the decode's pixels, so a rerun with the same peers
            // reads G'MIC's output from the cache.
            GmicResult g = run_gmic(peer.decoded, int(w) * 2, int(h) * 2, seed, stem + "_" + peer.codec, scratch,
                                    synth_cache, gmic_available);
            gmic_row.codec = peer.codec + "+gmic";
            gmic_row.setting = peer.setting + " then " + gmic_setting(seed) + (g.cached ? " cached" : "");
            add_gmic_row(gmic_row, g);
            if (g.status == "ok") sheet_panels.by_gmic = std::move(g.output);
            return sheet_panels;
        };
        for (const auto& [protocol, scale] : {std::pair{"same", 1}, {"large", 2}}) {
            Image syn;
            if (want(protocol) && synthesise(exemplar, int(w) * scale, int(h) * scale, seed, syn)) {
                Row r;
                r.protocol = protocol;
                r.codec = "ceiling:synth-from-exemplar";
                score(r, syn);
            }
        }
        if (want("large") && !no_peers) {
            // The same run as the synth protocol's G'MIC row (same key, so
            // one cache entry serves both).
            GmicResult g = run_gmic(exemplar, int(w) * 2, int(h) * 2, seed, stem, scratch, synth_cache, gmic_available);
            Row r;
            r.protocol = "large";
            r.codec = "ceiling:gmic-from-exemplar";
            r.setting = gmic_setting(seed) + (g.cached ? " cached" : "");
            add_gmic_row(r, g);
        }
        if (want("synth")) {
            // Both synthesisers start from the lossless exemplar.
            const int sw = synth_size ? int(synth_size) : int(w) * 2, sh = synth_size ? int(synth_size) : int(h) * 2;
            std::vector<Image> synth_panels{exemplar, held_out};
            Row r;
            r.protocol = "synth";
            r.codec = "vqtex";
            r.setting = "defaults threads=" + std::to_string(kSynthThreads);
            Image syn;
            vqtex_synth_stats stats{};
            long peak = 0;
            double wall = 0;
            if (synthesise_measured(exemplar, sw, sh, seed, scratch, syn, stats, peak, wall)) {
                r.encode_s = no_times ? 0 : stats.analyse_seconds;
                r.decode_s = no_times ? 0 : stats.synthesise_seconds;
                r.decode_peak_kib = no_times ? 0 : peak;
                r.wall_s = no_times ? 0 : wall;
                score(r, syn);
                synth_panels.push_back(std::move(syn));
            } else {
                r.status = "failed";
                r.texture = name;
                writer.add(r, floor);
                // A white panel keeps G'MIC's output in the fourth place.
                synth_panels.push_back(Image{sw, sh, 3, std::vector<uint8_t>(std::size_t(sw) * sh * 3, 255)});
            }
            if (!no_peers) {
                GmicResult g = run_gmic(exemplar, sw, sh, seed, stem, scratch, synth_cache, gmic_available);
                Row gr;
                gr.protocol = "synth";
                gr.codec = "gmic";
                gr.setting = gmic_setting(seed) + (g.cached ? " cached" : "");
                gr.status = g.status;
                gr.decode_s = gr.wall_s = no_times ? 0 : g.seconds;
                gr.decode_peak_kib = no_times ? 0 : g.peak_kib;
                if (g.status == "ok") {
                    score(gr, g.output);
                    synth_panels.push_back(std::move(g.output));
                } else {
                    gr.texture = name;
                    writer.add(gr, floor);
                }
            }
            if (!sheets.empty()) {
                fs::create_directories(sheets);
                write_sheet(fs::path(sheets) / ("synth_" + stem + ".png"), synth_panels);
            }
        }
        std::vector<int> points = qualities;
        if (!target_sizes.empty()) points.assign(target_sizes.begin(), target_sizes.end());
        for (int quality : rates ? points : std::vector<int>{}) {
            vqtex_encode_params ep;
            vqtex_encode_params_init(&ep);
            if (target_sizes.empty()) {
                ep.quality = uint32_t(quality);
                vqtex_encode_params_preset(&ep, quality);
            } else {
                ep.target_size = uint64_t(quality);
            }
            if (atlas) ep.codebook = VQTEX_CODEBOOK_ATLAS;
            ep.threads = 1;
            const std::string file = (scratch / "vqtex.vqt").string();
            long encode_peak = 0;
            double encode_s = 0;
            if (!measured([&] {
                    vqtex_image ex = view(exemplar);
                    uint8_t* data = nullptr;
                    size_t size = 0;
                    vqtex_error err{};
                    if (vqtex_encode(&ep, &ex, &data, &size, nullptr, &err) != VQTEX_OK) {
                        std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", name.c_str(), err.detail);
                        return false;
                    }
                    const vqtex_cpp::Buffer owned(data, size);
                    return write_all(file, owned.data(), owned.size());
                }, encode_peak, encode_s))
                return 1;
            const std::vector<uint8_t> bytes = read_all(file);
            const std::size_t size = bytes.size();
            Image vqtex_large_output;  // for the large protocol's sheet
            for (const auto& [protocol, scale] : {std::pair{"same", 1}, {"large", 2}}) {
                if (!want(protocol)) continue;
                vqtex_decode_params dp;
                vqtex_decode_params_init(&dp);
                dp.width = w * uint32_t(scale);
                dp.height = h * uint32_t(scale);
                dp.seed = seed;
                dp.threads = 1;
                const std::string raw = (scratch / "decoded.raw").string();
                long decode_peak = 0;
                double decode_s = 0;
                if (!measured([&] {
                        vqtex_cpp::Image dec;
                        vqtex_error err{};
                        if (vqtex_decode(&dp, bytes.data(), bytes.size(), dec.out(), &err) != VQTEX_OK) {
                            std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", name.c_str(), err.detail);
                            return false;
                        }
                        return write_all(raw, dec.data(), dec.size_bytes());
                    }, decode_peak, decode_s))
                    return 1;
                Image decoded{int(dp.width), int(dp.height), exemplar.channels, read_all(raw)};
                Row r;
                r.protocol = protocol;
                r.codec = atlas ? "vqtex-atlas" : "vqtex";
                r.quality = quality;
                r.setting = (target_sizes.empty() ? "-q " : "--target-size ") + std::to_string(quality) +
                            (atlas ? " --atlas" : "");
                r.bytes = size;
                r.encode_s = no_times ? 0 : encode_s;
                r.decode_s = no_times ? 0 : decode_s;
                r.encode_peak_kib = no_times ? 0 : encode_peak;
                r.decode_peak_kib = no_times ? 0 : decode_peak;
                score(r, decoded);
                if (scale == 2) vqtex_large_output = std::move(decoded);
            }
            std::vector<PeerSyntheses> peer_syntheses;
            if (!no_peers)
                for (PeerResult& peer : run_budgeted_peers(exemplar, size, scratch.string()))
                    peer_syntheses.push_back(add_peer_rows(peer, quality, true));
            if (!sheets.empty() && want("large")) {
                // Top row: exemplar | held-out | vqtex | each PEER+synth |
                // each PEER+gmic (peers in run_budgeted_peers' order, a blank
                // cell where a peer did not fit); under each synthesis, what
                // it was synthesised from: vqtex's decoded atlas, the peer's
                // decode (docs/METRICS.md).
                std::vector<Image> outputs{exemplar, held_out, vqtex_large_output};
                std::vector<Image> sources{Image{}, Image{}, decoded_atlas(bytes)};
                for (const PeerSyntheses& p : peer_syntheses)
                    outputs.push_back(p.by_vqtex), sources.push_back(p.decoded);
                for (const PeerSyntheses& p : peer_syntheses)
                    outputs.push_back(p.by_gmic), sources.push_back(p.decoded);
                fs::create_directories(sheets);
                write_sheet(fs::path(sheets) / ("large_" + stem + "_q" + std::to_string(quality) + ".png"),
                            {outputs, sources});
            }
        }
        if (!no_peers && rates)
            for (PeerResult& peer : run_astc(exemplar, scratch.string())) add_peer_rows(peer, -1, false);
        if (!sheets.empty()) {
            fs::create_directories(sheets);
            for (auto& [quality, images] : panels)
                write_sheet(fs::path(sheets) / (stem + "_q" + std::to_string(quality) + ".png"), images);
        }
        std::fprintf(stderr, "vqtex-bench: %s done\n", name.c_str());
    }
    std::error_code ec;
    fs::remove_all(scratch, ec);
    if (out) std::fclose(out);

    // Summary: mean over textures of each codec's scores per protocol and rate.
    struct Sum {
        double bytes = 0, swd = 0, completeness = 0, copy = 0, seam = 0;
        int n = 0;
    };
    std::map<std::tuple<std::string, int, std::string>, Sum> sums;
    for (const Row& r : writer.rows) {
        if (r.status != "ok" || r.protocol == "synth") continue;
        Sum& s = sums[{r.protocol, r.quality, r.codec}];
        s.bytes += double(r.bytes);
        s.swd += r.scores.swd.mean;
        s.completeness += r.scores.completeness;
        s.copy += r.scores.copy.exact_share;
        s.seam += r.scores.straight_seam;
        ++s.n;
    }
    if (rates)
        std::printf("%-6s %4s %-28s %9s %8s %8s %6s %6s %3s\n", "proto", "q", "codec", "bytes", "SWD", "compl",
                    "copy", "seam", "n");
    for (const auto& [key, s] : sums) {
        const auto& [protocol, quality, codec] = key;
        std::printf("%-6s %4d %-28s %9.0f %8.2f %8.2f %6.2f %6.2f %3d\n", protocol.c_str(), quality, codec.c_str(),
                    s.bytes / s.n, s.swd / s.n, s.completeness / s.n, s.copy / s.n, s.seam / s.n, s.n);
    }
    if (want("large")) print_large_summary(writer.rows);
    if (want("synth")) print_synth_summary(writer.rows, floors);
    return 0;
}
