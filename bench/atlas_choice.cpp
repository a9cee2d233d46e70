// atlas_choice.cpp - the study behind the encoder's choice of atlas (issue
// 17, docs/ATLAS.md "Which atlas"): for each photograph (exemplar = its
// top-left quarter, held-out = its bottom-right quarter, as vqtex-bench
// cuts them) and each byte target, every candidate region of the exemplar
// is coded as a format 5 file at the finest AV1 level that fits, decoded
// at 2x2 the exemplar with the public API, and scored twice:
//  * against the held-out crop (what the benchmark measures; the encoder
//    never sees it);
//  * against the exemplar itself (what the encoder can measure, its proxy).
// One CSV line per (texture, target, candidate), so that the oracle choice
// and the proxy's choice can be compared offline.
//
//   atlas-choice [--targets 1000,2000,4000] [--sides 128,96,64] IMAGE...
// The held-out scores are vqtex-bench's (score_all, seed 1), so
// bench/choice_rules.py can put them beside a bench run's peer rows.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/image.hpp"
#include "epitome.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "format/atlas_file.hpp"
#include "writer/atlas_writer.hpp"
#include "image_io.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"

namespace {

using vqtex::Image;

std::vector<int> parse_list(const char* s) {
    std::vector<int> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(std::atoi(item.c_str()));
    return v;
}

Image crop(const Image& src, int x0, int y0, int w, int h) {
    Image out(w, h, src.channels);
    for (int y = 0; y < h; ++y)
        std::memcpy(out.at(0, y), src.at(x0, y0 + y), std::size_t(w) * std::size_t(src.channels));
    return out;
}

vqtex_metrics::Image to_metrics(const Image& img) {
    return {img.width, img.height, img.channels, img.pixels};
}

std::vector<std::pair<int, int>> g_controls;

// An unsharp mask of `amount` percent over a [1 2 1]^2/16 blur (edges
// clamped), alpha untouched; a negative amount blends towards the blur.
// Does a sharper (or smoother) atlas come through AV1 with a lower SWD?
// (--sharpen, docs/studies/2026-11-24-atlas-choice-per-texture.md: no.)
Image sharpen(const Image& src, int amount) {
    if (amount == 0) return src;
    Image out = src;
    const int c = src.channels, colour = (c == 2 || c == 4) ? c - 1 : c;
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            for (int k = 0; k < colour; ++k) {
                int sum = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int sx = std::clamp(x + dx, 0, src.width - 1), sy = std::clamp(y + dy, 0, src.height - 1);
                        sum += (2 - std::abs(dx)) * (2 - std::abs(dy)) * src.at(sx, sy)[k];
                    }
                const int v = src.at(x, y)[k];
                const int s = v + int(std::lround(double((v * 16 - sum) * amount) / 1600.0));
                out.at(x, y)[k] = uint8_t(std::clamp(s, 0, 255));
            }
    return out;
}
int g_sharpen = 0;          // --sharpen: percent of unsharp mask (negative: blur) before coding
int g_fewer_levels = 0;     // --fewer-levels: the header's stack depth below the deepest
uint64_t g_proxy_seed = 2;  // the encoder's proxy seed (atlas_choice.cpp); --proxy-seed measures its noise

bool g_tileable = false;  // the atlas being coded wraps (an epitome)
vqtex::AtlasSynthesisParams g_params;  // the engine's, from --passes etc.
bool g_chroma444 = true;

std::vector<uint8_t> atlas_file(const Image& example, const Image& atlas, int cq, int speed) {
    vqtex::AtlasEncodeOptions o;
    o.controls = g_controls;
    o.chroma444 = g_chroma444;
    o.cq_level = cq;
    o.speed = speed;
    const std::vector<uint8_t> bits = vqtex::encode_atlas(sharpen(atlas, g_sharpen), o);
    vqtex::FileHeader h;
    h.exemplar_width = uint32_t(example.width);
    h.exemplar_height = uint32_t(example.height);
    h.channels = uint8_t(example.channels);
    h.levels = uint8_t(std::max(1, vqtex::coherent_levels(atlas.width, atlas.height) - g_fewer_levels));
    h.seed = 1;
    vqtex::AtlasSynthesisParams sp = g_params;
    sp.example_tileable = g_tileable;
    return vqtex::encode_atlas_file(h, atlas.width, atlas.height, bits, sp);
}

// The finest level whose file fits, or an empty file. `coded` keeps the
// files of the levels tried, which the targets share.
std::vector<uint8_t> fit(const Image& example, const Image& atlas, std::size_t target, int speed, int* cq_out,
                         std::map<int, std::vector<uint8_t>>& coded) {
    auto file_at = [&](int cq) -> const std::vector<uint8_t>& {
        auto it = coded.find(cq);
        if (it == coded.end()) it = coded.emplace(cq, atlas_file(example, atlas, cq, speed)).first;
        return it->second;
    };
    std::vector<uint8_t> best = file_at(63);
    if (best.size() > target) return {};
    int lo = 0, hi = 62, cq = 63;
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        const std::vector<uint8_t>& f = file_at(mid);
        if (f.size() <= target) {
            best = f;
            cq = mid;
            hi = mid - 1;
        } else {
            lo = mid + 1;
        }
    }
    *cq_out = cq;
    return best;
}

Image decode(const std::vector<uint8_t>& file, int w, int h, uint64_t seed) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = uint32_t(w);
    p.height = uint32_t(h);
    p.seed = seed;
    p.threads = 2;
    vqtex_image out;
    vqtex_error err;
    if (vqtex_decode(&p, file.data(), file.size(), &out, &err) != VQTEX_OK) {
        std::fprintf(stderr, "decode failed: %s\n", err.detail);
        std::exit(1);
    }
    Image img(int(out.width), int(out.height), int(out.channels));
    std::memcpy(img.pixels.data(), out.pixels, img.pixels.size());
    vqtex_image_free(&out);
    return img;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> targets{1000, 2000, 4000};
    std::vector<int> sides{128, 112, 96, 80, 64, 48};
    std::vector<int> epitomes;
    vqtex::EpitomeOptions eo;
    eo.threads = 2;
    std::string dump;
    int speed = 4;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--targets" && i + 1 < argc) targets = parse_list(argv[++i]);
        else if (a == "--sides" && i + 1 < argc) sides = parse_list(argv[++i]);
        else if (a == "--speed" && i + 1 < argc) speed = std::atoi(argv[++i]);
        else if (a == "--sharpen" && i + 1 < argc) g_sharpen = std::atoi(argv[++i]);
        else if (a == "--proxy-seed" && i + 1 < argc) g_proxy_seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--fewer-levels" && i + 1 < argc) g_fewer_levels = std::atoi(argv[++i]);
        else if (a == "--epitomes" && i + 1 < argc) epitomes = parse_list(argv[++i]);
        else if (a == "--patch" && i + 1 < argc) eo.patch = std::atoi(argv[++i]);
        else if (a == "--stride" && i + 1 < argc) eo.stride = std::atoi(argv[++i]);
        else if (a == "--iterations" && i + 1 < argc) eo.iterations = std::atoi(argv[++i]);
        else if (a == "--dump" && i + 1 < argc) dump = argv[++i];
        else if (a == "--sharp") eo.sharp = true;
        else if (a == "--420") g_chroma444 = false;
        else if (a == "--passes" && i + 1 < argc) g_params.passes = std::atoi(argv[++i]);
        else if (a == "--coarse-passes" && i + 1 < argc) g_params.coarse_passes = std::atoi(argv[++i]);
        else if (a == "--polish" && i + 1 < argc) g_params.polish_passes = std::atoi(argv[++i]);
        else if (a == "--coherence" && i + 1 < argc) g_params.coherence = std::atoi(argv[++i]);
        else if (a == "--bias" && i + 1 < argc) g_params.coherence_bias = std::atoi(argv[++i]);
        else if (a == "--jitter" && i + 1 < argc) g_params.jitter = std::atoi(argv[++i]);
        else if (a == "--aom" && i + 1 < argc) {  // id=value,...
            std::stringstream ss(argv[++i]);
            std::string item;
            while (std::getline(ss, item, ','))
                g_controls.push_back({std::atoi(item.c_str()), std::atoi(item.c_str() + item.find('=') + 1)});
        }
        else files.push_back(a);
    }
    std::printf("texture,target,side,x,y,cq,bytes,h_compl,h_swd,h_coh,p_compl,p_swd,p_coh\n");
    for (const std::string& f : files) {
        const vqtex_tools::LoadedImage li = vqtex_tools::load_image(f);
        Image whole(int(li.width), int(li.height), int(li.channels));
        whole.pixels = li.pixels;
        const int w = whole.width / 2, h = whole.height / 2;
        const Image exemplar = crop(whole, 0, 0, w, h), held = crop(whole, w, h, w, h);
        const std::string name = f.substr(f.find_last_of('/') + 1);
        struct Candidate {
            int side, x, y;  // x = -1: an epitome
            Image atlas;
        };
        std::vector<Candidate> candidates;
        for (int side : sides) {
            if (side > w || side > h) continue;
            candidates.push_back({side, 0, 0, crop(exemplar, 0, 0, side, side)});
            if (side < w)
                candidates.push_back({side, (w - side) / 2, (h - side) / 2,
                                      crop(exemplar, (w - side) / 2, (h - side) / 2, side, side)});
        }
        for (int side : epitomes) {
            eo.width = eo.height = side;
            candidates.push_back({side, -1, -1, vqtex::learn_epitome(exemplar, eo)});
            if (!dump.empty())
                vqtex_tools::save_image(dump + "/" + name + "_epitome" + std::to_string(side) + ".png", uint32_t(side),
                                        uint32_t(side), uint32_t(exemplar.channels), candidates.back().atlas.pixels.data());
        }
        for (const Candidate& cand : candidates) {
            g_tileable = cand.x < 0;
            std::map<int, std::vector<uint8_t>> coded;
            for (int target : targets) {
                int cq = -1;
                const std::vector<uint8_t> file = fit(exemplar, cand.atlas, std::size_t(target), speed, &cq, coded);
                if (file.empty()) continue;
                const Image out = decode(file, 2 * w, 2 * h, 1);
                const auto om = to_metrics(out), hm = to_metrics(held);
                // The held-out scores as vqtex-bench computes them (score_all,
                // seed 1: its metric seeds differ from the defaults, and one
                // SWD sample moves by several hundredths with them).
                const vqtex_metrics::Scores bench = vqtex_metrics::score_all(om, hm, to_metrics(exemplar), 1);
                const double hc = bench.completeness;
                const double hs = bench.swd.mean;
                const Image proxy = decode(file, 2 * w, 2 * h, g_proxy_seed);
                const auto pm = to_metrics(proxy), em = to_metrics(exemplar);
                const double pc = vqtex_metrics::completeness(em, pm);
                const double ps = vqtex_metrics::sliced_wasserstein(pm, em).mean;
                const double ph = vqtex_metrics::coherence(pm, em);
                const double hh = bench.coherence;
                std::printf("%s,%d,%d,%d,%d,%d,%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n", name.c_str(), target, cand.side,
                            cand.x, cand.y, cq, file.size(), hc, hs, hh, pc, ps, ph);
                std::fflush(stdout);
            }
        }
    }
    return 0;
}
