// bench_peers.hpp - the peer codecs of vqtex-bench, run as Debian's command
// line tools at a byte budget: JPEG (cjpeg, quality search), WebP (cwebp
// -size), AVIF (avifenc 0.11, --min/--max quantizer search), JPEG XL (cjxl
// 0.7, distance search) and ASTC (astcenc, fixed block sizes). A missing
// tool is reported, never fatal.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "metrics.hpp"

namespace vqtex_tools {

struct PeerResult {
    std::string codec;        // "jpeg", "webp", "avif", "jxl", "astc-6x6", ...
    bool available = false;   // the tool exists
    bool fits = false;        // a setting met the budget (always true for ASTC)
    std::size_t bytes = 0;
    std::string setting;      // the quality setting used
    vqtex_metrics::Image decoded;
    long encode_peak_kib = 0;  // peak resident memory of the final encode / decode process
    long decode_peak_kib = 0;
    double encode_s = 0, decode_s = 0;
};

// Runs a shell command; returns its exit status and, through the pointers,
// the peak resident memory (KiB) and wall time of the process tree it ran.
int run_measured(const std::string& command, long* peak_kib = nullptr, double* seconds = nullptr);

// Every budgeted peer at `budget` bytes (or those named in `only`);
// temporary files go into `dir`.
std::vector<PeerResult> run_budgeted_peers(const vqtex_metrics::Image& exemplar, std::size_t budget,
                                           const std::string& dir, const std::vector<std::string>& only = {});

// ASTC at its fixed rates (block sizes 4x4 to 12x12: 8 to 0.89 bits per pixel).
std::vector<PeerResult> run_astc(const vqtex_metrics::Image& exemplar, const std::string& dir);

bool tool_available(const std::string& name);

}  // namespace vqtex_tools
