// sequence_io.cpp - reading and writing frame sequences (see
// sequence_io.hpp).
#include "sequence_io.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "image_io.hpp"
#include "imageio_module.hpp"

namespace vqtex_tools {

namespace fs = std::filesystem;

namespace {

constexpr uint32_t kMaxFrames = 65536;

const std::regex& pattern_regex() {
    static const std::regex r("%0?[0-9]*d");
    return r;
}

std::string frame_name(const std::string& pattern, uint32_t t) {
    std::smatch m;
    std::regex_search(pattern, m, pattern_regex());
    char buf[32];
    std::snprintf(buf, sizeof buf, m.str().c_str(), int(t));
    return m.prefix().str() + buf + m.suffix().str();
}

int subimage_count(const std::string& path) {
    const ImageioModule& io = imageio();
    const QuietStderr quiet;
    return io.subimage_count(path);
}

void append_frame(LoadedSequence& seq, const LoadedImage& img, const std::string& name) {
    if (seq.frames == 0) {
        seq.width = img.width;
        seq.height = img.height;
        seq.channels = img.channels;
        seq.notice = img.notice;
    } else if (img.width != seq.width || img.height != seq.height || img.channels != seq.channels) {
        throw std::runtime_error("frame '" + name + "' is " + std::to_string(img.width) + "x" +
                                 std::to_string(img.height) + " with " + std::to_string(img.channels) +
                                 " channels, unlike the first frame (" + std::to_string(seq.width) + "x" +
                                 std::to_string(seq.height) + ", " + std::to_string(seq.channels) +
                                 "): all frames must match");
    }
    if (seq.frames >= kMaxFrames) throw std::runtime_error("more than " + std::to_string(kMaxFrames) + " frames");
    seq.pixels.insert(seq.pixels.end(), img.pixels.begin(), img.pixels.end());
    ++seq.frames;
}

}  // namespace

bool is_frame_pattern(const std::string& path) {
    const auto begin = std::sregex_iterator(path.begin(), path.end(), pattern_regex());
    return std::distance(begin, std::sregex_iterator()) == 1;
}

bool is_sequence(const std::string& path) {
    if (is_frame_pattern(path) || fs::is_directory(path)) return true;
    return fs::exists(path) && subimage_count(path) > 1;
}

void check_animation_request(const std::string& input, bool animation, const std::string& verb) {
    std::error_code ec;
    if (fs::is_directory(input, ec) && !animation)
        throw std::invalid_argument("'" + input + "' is a folder: add --animation to " + verb +
                                    " its images as the frames of one animation, or give -o DIR to " + verb +
                                    " each image on its own into DIR");
    if (animation && !is_sequence(input))
        throw std::invalid_argument("--animation: '" + input +
                                    "' is not an animation (a folder of frames, a numbered pattern such as "
                                    "'frames/frame_%03d.png', or a multi-image file)");
}

LoadedSequence load_sequence(const std::string& path) {
    LoadedSequence seq;
    if (is_frame_pattern(path)) {
        // Numbered from 0 or from 1, up to the first missing number.
        const uint32_t first = fs::exists(frame_name(path, 0)) ? 0 : 1;
        if (!fs::exists(frame_name(path, first)))
            throw std::runtime_error("no frame of '" + path + "' found (tried '" + frame_name(path, 0) + "' and '" +
                                     frame_name(path, 1) + "')");
        for (uint32_t t = first; fs::exists(frame_name(path, t)); ++t) {
            const std::string name = frame_name(path, t);
            append_frame(seq, load_image(name), name);
        }
    } else if (fs::is_directory(path)) {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(path))
            if (e.is_regular_file() && e.path().filename().string()[0] != '.') names.push_back(e.path().string());
        std::sort(names.begin(), names.end());
        if (names.empty()) throw std::runtime_error("folder '" + path + "' holds no frames");
        for (const std::string& name : names) append_frame(seq, load_image(name), name);
    } else {
        if (!fs::exists(path)) throw std::runtime_error("cannot read '" + path + "': no such file");
        const ImageioModule& io = imageio();
        const QuietStderr quiet;
        io.read_subimages(path, [&](LoadedImage&& img) { append_frame(seq, img, path); });
    }
    return seq;
}

std::vector<std::string> save_sequence(const std::string& pattern, const vqtex_volume& v) {
    if (!is_frame_pattern(pattern))
        throw std::runtime_error("output '" + pattern + "' needs one frame-number field, e.g. out/frame_%03d.png");
    const fs::path folder = fs::path(frame_name(pattern, 0)).parent_path();
    if (!folder.empty() && !fs::is_directory(folder))
        throw std::runtime_error("cannot write '" + pattern + "': folder '" + folder.string() + "' does not exist");
    std::vector<std::string> finals, temps;
    const std::size_t frame_bytes = std::size_t(v.width) * v.height * v.channels;
    auto cleanup = [&] {
        std::error_code ec;
        for (const std::string& t : temps) fs::remove(t, ec);
    };
    try {
        for (uint32_t t = 0; t < v.frames; ++t) {
            finals.push_back(frame_name(pattern, t));
            // save_image itself writes atomically; here the whole sequence
            // is staged under temporary names first.
            temps.push_back(temporary_name_for(finals.back()));
            save_image(temps.back(), v.width, v.height, v.channels, v.pixels + frame_bytes * t);
        }
        refuse_folders(finals);
        for (std::size_t i = 0; i < finals.size(); ++i) {
            std::error_code ec;
            fs::rename(temps[i], finals[i], ec);
            if (ec) throw std::runtime_error("cannot write '" + finals[i] + "': " + ec.message());
        }
    } catch (...) {
        cleanup();
        throw;
    }
    return finals;
}

void parse_shapes3(const std::string& text, vqtex_shape3 shapes[VQTEX_MAX_LEVELS]) {
    std::stringstream ss(text);
    std::string item;
    int level = 0;
    while (std::getline(ss, item, ',')) {
        if (level >= VQTEX_MAX_LEVELS) throw std::invalid_argument("too many shapes in '" + text + "'");
        unsigned r = 0, c = 0, d = 0, k = 0;
        char x1 = 0, x2 = 0, colon = 0, extra = 0;
        const int n = std::sscanf(item.c_str(), "%u%c%u%c%u%c%u%c", &r, &x1, &c, &x2, &d, &colon, &k, &extra);
        if (n != 7 || x1 != 'x' || x2 != 'x' || colon != ':' || r % 2 == 0 || c % 2 == 0 || d % 2 == 0 || k < 1 ||
            r > 31 || c > 31 || d > 31 || k > 8)
            throw std::invalid_argument("shape '" + item + "' is not RxCxD:k with odd R, C, D up to 31 (e.g. 5x5x5:2)");
        shapes[level++] = vqtex_shape3{uint8_t(r), uint8_t(c), uint8_t(d), uint8_t(k)};
    }
}

}  // namespace vqtex_tools
