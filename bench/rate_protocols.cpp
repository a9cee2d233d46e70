// vqtex-bench's same and large protocols (see rate_protocols.hpp).
#include "rate_protocols.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bench_peers.hpp"
#include "contact_sheet.hpp"
#include "measured_run.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"
#include "vqtex_runs.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

// What a budgeted peer gives the large protocol's contact sheet:
// its decode and the two syntheses from it (empty when absent).
struct PeerSyntheses {
    Image decoded, by_vqtex, by_gmic;
};

// A peer's rows: its decode as is, tiled to the larger output, and
// (budgeted peers) synthesised to it by vqtex's engine and by G'MIC.
PeerSyntheses add_peer_rows(TextureRun& t, PeerResult& peer, int quality, bool with_synthesis) {
    PeerSyntheses sheet_panels;
    Row r;
    r.codec = peer.codec;
    r.quality = quality;
    r.setting = peer.setting;
    r.bytes = peer.bytes;
    r.encode_s = t.o.no_times ? 0 : peer.encode_s;
    r.decode_s = t.o.no_times ? 0 : peer.decode_s;
    r.encode_peak_kib = t.o.no_times ? 0 : peer.encode_peak_kib;
    r.decode_peak_kib = t.o.no_times ? 0 : peer.decode_peak_kib;
    r.protocol = t.o.want("same") ? "same" : "large";
    if (!peer.available || !peer.fits) {
        r.status = !peer.available ? "missing" : with_synthesis ? "no-fit" : "failed";
        t.add_status(r);
        return sheet_panels;
    }
    // The decode as it is (exemplar-sized) is a same-protocol row only:
    // r.protocol says "large" above when same is not run, for the status
    // rows, and a large run then also scored the small decode under the
    // peer's name, beside its tiled decode.
    r.protocol = "same";
    t.score(r, peer.decoded);
    r.protocol = "large";
    t.score(r, tiled(peer.decoded, int(t.w) * 2, int(t.h) * 2));
    if (!with_synthesis || !t.o.want("large")) return sheet_panels;
    sheet_panels.decoded = peer.decoded;
    // Both rows keep the peer's bytes, setting and coding times: the
    // synthesis cost is the synth protocol's to measure.
    Row synth_row = r, gmic_row = r;
    if (synthesise(peer.decoded, int(t.w) * 2, int(t.h) * 2, t.o.seed, sheet_panels.by_vqtex)) {
        synth_row.codec = peer.codec + "+synth";
        t.score(synth_row, sheet_panels.by_vqtex);
    }
    // Keyed by the decode's pixels, so a rerun with the same peers
    // reads G'MIC's output from the cache.
    GmicResult g = run_gmic(peer.decoded, int(t.w) * 2, int(t.h) * 2, t.o.seed, t.stem + "_" + peer.codec,
                            t.scratch, t.o.synth_cache, t.gmic_available);
    gmic_row.codec = peer.codec + "+gmic";
    gmic_row.setting = peer.setting + " then " + gmic_setting(t.o.seed) + (g.cached ? " cached" : "");
    t.add_gmic_row(gmic_row, g);
    if (g.status == "ok") sheet_panels.by_gmic = std::move(g.output);
    return sheet_panels;
}

}  // namespace

void run_ceilings(TextureRun& t) {
    for (const auto& [protocol, scale] : {std::pair{"same", 1}, {"large", 2}}) {
        Image syn;
        if (t.o.want(protocol) && synthesise(t.exemplar, int(t.w) * scale, int(t.h) * scale, t.o.seed, syn)) {
            Row r;
            r.protocol = protocol;
            r.codec = "ceiling:synth-from-exemplar";
            t.score(r, syn);
        }
    }
    if (t.o.want("large") && !t.o.no_peers) {
        // The same run as the synth protocol's G'MIC row (same key, so
        // one cache entry serves both).
        GmicResult g = run_gmic(t.exemplar, int(t.w) * 2, int(t.h) * 2, t.o.seed, t.stem, t.scratch, t.o.synth_cache,
                                t.gmic_available);
        Row r;
        r.protocol = "large";
        r.codec = "ceiling:gmic-from-exemplar";
        r.setting = gmic_setting(t.o.seed) + (g.cached ? " cached" : "");
        t.add_gmic_row(r, g);
    }
}

bool run_rate_points(TextureRun& t) {
    std::vector<int> points = t.o.qualities;
    if (!t.o.target_sizes.empty()) points.assign(t.o.target_sizes.begin(), t.o.target_sizes.end());
    for (int quality : t.o.rates() ? points : std::vector<int>{}) {
        vqtex_encode_params ep;
        vqtex_encode_params_init(&ep);
        if (t.o.target_sizes.empty()) {
            ep.quality = uint32_t(quality);
            vqtex_encode_params_preset(&ep, quality);
        } else {
            ep.target_size = uint64_t(quality);
        }
        if (t.o.atlas) ep.codebook = VQTEX_CODEBOOK_ATLAS;
        ep.threads = 1;
        const std::string file = (t.scratch / "vqtex.vqt").string();
        long encode_peak = 0;
        double encode_s = 0;
        if (!measured([&] {
                vqtex_image ex = view(t.exemplar);
                uint8_t* data = nullptr;
                size_t size = 0;
                vqtex_error err{};
                if (vqtex_encode(&ep, &ex, &data, &size, nullptr, &err) != VQTEX_OK) {
                    std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", t.name.c_str(), err.detail);
                    return false;
                }
                const vqtex_cpp::Buffer owned(data, size);
                return write_all(file, owned.data(), owned.size());
            }, encode_peak, encode_s))
            return false;
        const std::vector<uint8_t> bytes = read_all(file);
        const std::size_t size = bytes.size();
        Image vqtex_large_output;  // for the large protocol's sheet
        for (const auto& [protocol, scale] : {std::pair{"same", 1}, {"large", 2}}) {
            if (!t.o.want(protocol)) continue;
            vqtex_decode_params dp;
            vqtex_decode_params_init(&dp);
            dp.width = t.w * uint32_t(scale);
            dp.height = t.h * uint32_t(scale);
            dp.seed = t.o.seed;
            dp.threads = 1;
            const std::string raw = (t.scratch / "decoded.raw").string();
            long decode_peak = 0;
            double decode_s = 0;
            if (!measured([&] {
                    vqtex_cpp::Image dec;
                    vqtex_error err{};
                    if (vqtex_decode(&dp, bytes.data(), bytes.size(), dec.out(), &err) != VQTEX_OK) {
                        std::fprintf(stderr, "vqtex-bench: error: %s: %s\n", t.name.c_str(), err.detail);
                        return false;
                    }
                    return write_all(raw, dec.data(), dec.size_bytes());
                }, decode_peak, decode_s))
                return false;
            Image decoded{int(dp.width), int(dp.height), t.exemplar.channels, read_all(raw)};
            Row r;
            r.protocol = protocol;
            r.codec = t.o.atlas ? "vqtex-atlas" : "vqtex";
            r.quality = quality;
            r.setting = (t.o.target_sizes.empty() ? "-q " : "--target-size ") + std::to_string(quality) +
                        (t.o.atlas ? " --atlas" : "");
            r.bytes = size;
            r.encode_s = t.o.no_times ? 0 : encode_s;
            r.decode_s = t.o.no_times ? 0 : decode_s;
            r.encode_peak_kib = t.o.no_times ? 0 : encode_peak;
            r.decode_peak_kib = t.o.no_times ? 0 : decode_peak;
            t.score(r, decoded);
            if (scale == 2) vqtex_large_output = std::move(decoded);
        }
        std::vector<PeerSyntheses> peer_syntheses;
        if (!t.o.no_peers)
            for (PeerResult& peer : run_budgeted_peers(t.exemplar, size, t.scratch.string()))
                peer_syntheses.push_back(add_peer_rows(t, peer, quality, true));
        if (!t.o.sheets.empty() && t.o.want("large")) {
            // Top row: exemplar | held-out | vqtex | each PEER+synth |
            // each PEER+gmic (peers in run_budgeted_peers' order, a blank
            // cell where a peer did not fit); under each synthesis, what
            // it was synthesised from: vqtex's decoded atlas, the peer's
            // decode (docs/METRICS.md).
            std::vector<Image> outputs{t.exemplar, t.held_out, vqtex_large_output};
            std::vector<Image> sources{Image{}, Image{}, decoded_atlas(bytes)};
            for (const PeerSyntheses& p : peer_syntheses)
                outputs.push_back(p.by_vqtex), sources.push_back(p.decoded);
            for (const PeerSyntheses& p : peer_syntheses)
                outputs.push_back(p.by_gmic), sources.push_back(p.decoded);
            fs::create_directories(t.o.sheets);
            write_sheet(fs::path(t.o.sheets) / ("large_" + t.stem + "_q" + std::to_string(quality) + ".png"),
                        {outputs, sources});
        }
    }
    if (!t.o.no_peers && t.o.rates())
        for (PeerResult& peer : run_astc(t.exemplar, t.scratch.string())) add_peer_rows(t, peer, -1, false);
    if (!t.o.sheets.empty()) {
        fs::create_directories(t.o.sheets);
        for (auto& [quality, images] : t.panels)
            write_sheet(fs::path(t.o.sheets) / (t.stem + "_q" + std::to_string(quality) + ".png"), images);
    }
    return true;
}

}  // namespace vqtex_tools
