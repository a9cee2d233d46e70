// cli_common.cpp - shared parsing and progress display for the tools.
#include "cli_common.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace vqtex_tools {

void parse_size(const std::string& text, uint32_t& width, uint32_t& height) {
    unsigned long w = 0, h = 0;
    char x = 0, extra = 0;
    const int n = std::sscanf(text.c_str(), "%lu%c%lu%c", &w, &x, &h, &extra);
    if (n == 1) {
        h = w;
    } else if (!(n == 3 && (x == 'x' || x == 'X'))) {
        throw std::invalid_argument("size '" + text + "' is not WIDTHxHEIGHT (e.g. 512x512)");
    }
    if (w < 1 || h < 1 || w > 65536 || h > 65536)
        throw std::invalid_argument("size '" + text + "' is out of range");
    width = uint32_t(w);
    height = uint32_t(h);
}

void parse_shapes(const std::string& text, vqtex_shape (&shapes)[VQTEX_MAX_LEVELS]) {
    std::stringstream ss(text);
    std::string item;
    int level = 0;
    while (std::getline(ss, item, ',')) {
        if (level >= VQTEX_MAX_LEVELS) throw std::invalid_argument("too many shapes in '" + text + "'");
        unsigned r = 0, c = 0, k = 0;
        char x = 0, colon = 0, extra = 0;
        const int n = std::sscanf(item.c_str(), "%u%c%u%c%u%c", &r, &x, &c, &colon, &k, &extra);
        if (n != 5 || x != 'x' || colon != ':' || r % 2 == 0 || c % 2 == 0 || k < 1 || r > 63 ||
            c > 63 || k > 8)
            throw std::invalid_argument("shape '" + item +
                                        "' is not RxC:k with odd R, C up to 63 (e.g. 9x9:2)");
        shapes[level++] = vqtex_shape{uint8_t(r), uint8_t(c), uint8_t(k)};
    }
}

void parse_codewords(const std::string& text, vqtex_tsvq_params& params) {
    if (text.find('.') != std::string::npos) {
        char* end = nullptr;
        const double f = std::strtod(text.c_str(), &end);
        if (*end != '\0' || !(f > 0 && f <= 1))
            throw std::invalid_argument("codeword fraction '" + text + "' must be in (0, 1]");
        params.codeword_fraction = float(f);
        for (auto& c : params.codewords) c = 0;
        return;
    }
    std::stringstream ss(text);
    std::string item;
    std::vector<uint32_t> values;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        const unsigned long v = std::strtoul(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || v < 1 || v > 100000000)
            throw std::invalid_argument("codeword count '" + item + "' must be a positive integer");
        values.push_back(uint32_t(v));
    }
    if (values.empty() || values.size() > VQTEX_MAX_LEVELS)
        throw std::invalid_argument("codewords '" + text + "': give 1 to 8 counts");
    for (int l = 0; l < VQTEX_MAX_LEVELS; ++l)
        params.codewords[l] = values.size() == 1 ? values[0] : (size_t(l) < values.size() ? values[size_t(l)] : 0);
}

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

ProgressBar::ProgressBar(bool on) : enabled(on && ::isatty(2)), started(now_seconds()) {}

ProgressBar::~ProgressBar() { finish(); }

int ProgressBar::callback(void* user, vqtex_stage stage, uint64_t done, uint64_t total) {
    auto* bar = static_cast<ProgressBar*>(user);
    if (!bar->enabled || total == 0 || now_seconds() - bar->started < 1.0) return 1;
    const int width = 30;
    const int filled = int(double(done) / double(total) * width);
    std::fprintf(stderr, "\r%-10s [%.*s%*s] %3d%%", stage == VQTEX_STAGE_ANALYSE ? "analysing" : "synthesis",
                 filled, "##############################", width - filled, "",
                 int(100.0 * double(done) / double(total)));
    bar->drawn = true;
    return 1;
}

void ProgressBar::finish() {
    if (drawn) std::fprintf(stderr, "\r%60s\r", "");
    drawn = false;
}

}  // namespace vqtex_tools
