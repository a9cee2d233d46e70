// image_io.cpp - OpenImageIO-backed image reading and atomic writing.
#include "image_io.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

namespace fs = std::filesystem;

std::string temporary_name_for(const std::string& path) {
    const fs::path p(path);
    const std::string name = "." + p.stem().string() + ".tmp" + std::to_string(::getpid()) +
                             p.extension().string();
    return (p.parent_path() / name).string();
}

namespace {

// Temporary files being written, removed by a signal handler if SIGINT,
// SIGTERM or SIGHUP stops the program first (SIGKILL cannot be caught: then
// the temporary stays, under its recognisable .NAME.tmpPID.EXT, and the
// output it was meant to replace is untouched all the same). Fixed storage:
// the handler may only call async-signal-safe functions.
constexpr int kPendingSlots = 40;
char g_pending[kPendingSlots][4096];
volatile std::sig_atomic_t g_pending_used[kPendingSlots];

extern "C" void remove_pending_and_die(int sig) {
    for (int i = 0; i < kPendingSlots; ++i)
        if (g_pending_used[i]) ::unlink(g_pending[i]);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

void install_cleanup_handlers() {
    static const bool installed = [] {
        for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction old{};
            // Leave a signal the caller chose to ignore ignored.
            if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_DFL)
                std::signal(sig, remove_pending_and_die);
        }
        return true;
    }();
    (void)installed;
}

void track(const std::string& tmp) {
    install_cleanup_handlers();
    for (int i = 0; i < kPendingSlots; ++i)
        if (!g_pending_used[i] && tmp.size() < sizeof g_pending[i]) {
            std::memcpy(g_pending[i], tmp.c_str(), tmp.size() + 1);
            g_pending_used[i] = 1;
            return;
        }
}

void untrack(const std::string& tmp) {
    for (int i = 0; i < kPendingSlots; ++i)
        if (g_pending_used[i] && tmp == g_pending[i]) g_pending_used[i] = 0;
}

// Moves a finished temporary file into place; on failure removes it, so a
// failed write never leaves anything behind. Throws naming `path`.
void commit_temporary(const std::string& tmp, const std::string& path, bool ok, const std::string& why) {
    std::error_code ec;
    untrack(tmp);
    if (!ok) {
        fs::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path + "': " + why);
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        const std::string message = ec.message();
        fs::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path + "': " + message);
    }
}

}  // namespace

QuietStderr::QuietStderr() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (file_) saved_ = ::dup(2);
    if (saved_ >= 0 && ::dup2(::fileno(file_), 2) < 0) {
        ::close(saved_);
        saved_ = -1;
    }
}

QuietStderr::~QuietStderr() {
    std::fflush(stderr);
    std::cerr.flush();
    if (saved_ >= 0) {
        ::dup2(saved_, 2);
        ::close(saved_);
    }
    if (file_) std::fclose(file_);
}

namespace {

// OpenImageIO's errors may span lines (one per layer that saw them).
std::string one_line(std::string why) {
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    for (std::size_t at; (at = why.find('\n')) != std::string::npos;) why.replace(at, 1, "; ");
    return why;
}

// libjpeg fills a JPEG cut short with grey and only warns. The entropy-coded
// data cannot contain FF D9 (an FF there is always followed by 00 or a
// restart marker), so a complete scan shows an end-of-image marker after
// its first start-of-scan marker.
bool jpeg_is_complete(const std::vector<uint8_t>& b) {
    std::size_t i = 0;
    while (i + 1 < b.size() && !(b[i] == 0xFF && b[i + 1] == 0xDA)) ++i;
    for (; i + 1 < b.size(); ++i)
        if (b[i] == 0xFF && b[i + 1] == 0xD9) return true;
    return false;
}

LoadedImage load_image_quietly(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = one_line(OIIO::geterror());
        if (why.empty()) why = "not an image format OpenImageIO can read";
        throw std::runtime_error("cannot read '" + path + "': " + why);
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0)
        throw std::runtime_error("'" + path + "' has zero size (" + std::to_string(spec.width) +
                                 "x" + std::to_string(spec.height) + ")");
    if (spec.depth > 1)
        throw std::runtime_error("'" + path + "' is a volume image; only 2D images are supported");
    const uint64_t pixels = uint64_t(spec.width) * uint64_t(spec.height);
    if (spec.width > 65536 || spec.height > 65536 || pixels > (uint64_t(1) << 30))
        throw std::runtime_error("'" + path + "' is " + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) +
                                 ", larger than the 65536-per-side, 2^30-pixel limit");
    LoadedImage img;
    img.width = uint32_t(spec.width);
    img.height = uint32_t(spec.height);
    img.channels = uint32_t(std::min(spec.nchannels, 4));
    if (spec.nchannels > 4)
        img.notice = "kept the first 4 of " + std::to_string(spec.nchannels) + " channels";
    if (spec.format != OIIO::TypeDesc::UINT8) {
        if (!img.notice.empty()) img.notice += "; ";
        img.notice += "converted " + std::string(spec.format.c_str()) +
                      " samples to 8 bits (rounded, clamped to 0..1 for float)";
    }
    // Strips of rows, the buffer growing with them: a header that declares
    // a huge image over a short (truncated or forged) body fails after
    // allocating about what the file really holds, not what it claims.
    const std::size_t row_bytes = std::size_t(spec.width) * img.channels;
    constexpr int kStripRows = 64;
    for (int y = 0; y < spec.height; y += kStripRows) {
        const int rows = std::min(kStripRows, spec.height - y);
        img.pixels.resize((std::size_t(y) + std::size_t(rows)) * row_bytes);
        if (!in->read_scanlines(0, 0, spec.y + y, spec.y + y + rows, 0, 0, int(img.channels), OIIO::TypeDesc::UINT8,
                                img.pixels.data() + std::size_t(y) * row_bytes)) {
            const std::string why = one_line(in->geterror());
            throw std::runtime_error("cannot decode '" + path + "' (rows " + std::to_string(y) + " to " +
                                     std::to_string(y + rows - 1) + " of " + std::to_string(spec.height) +
                                     "): " + (why.empty() ? std::string("read failed") : why) +
                                     ": the file is damaged or truncated");
        }
    }
    if (std::string(in->format_name()) == "jpeg" && !jpeg_is_complete(load_bytes(path)))
        throw std::runtime_error("cannot decode '" + path +
                                 "': the JPEG data ends before its end-of-image marker: the file is truncated");
    in->close();
    return img;
}

}  // namespace

LoadedImage load_image(const std::string& path) {
    if (!fs::exists(path)) throw std::runtime_error("cannot read '" + path + "': no such file");
    if (fs::is_directory(path)) throw std::runtime_error("cannot read '" + path + "': it is a folder, not an image");
    const QuietStderr quiet;
    return load_image_quietly(path);
}

namespace {

// Writes an image to a temporary name beside `path` and returns that name;
// on failure removes it and throws naming `path`.
std::string write_temporary(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                            const uint8_t* pixels) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out)
        throw std::runtime_error("cannot write '" + path + "': unknown image format for this extension (" +
                                 OIIO::geterror() + ")");
    OIIO::ImageSpec spec(int(width), int(height), int(channels), OIIO::TypeDesc::UINT8);
    const std::string tmp = temporary_name_for(path);
    track(tmp);
    const bool ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels) && out->close();
    if (!ok) commit_temporary(tmp, path, false, out->geterror());  // removes tmp, throws
    return tmp;
}

}  // namespace

void save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                const uint8_t* pixels) {
    commit_temporary(write_temporary(path, width, height, channels, pixels), path, true, "");
}

std::vector<uint8_t> load_bytes(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot read '" + path + "': " + (fs::exists(path) ? "permission denied" : "no such file"));
    std::vector<uint8_t> bytes;
    uint8_t buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) throw std::runtime_error("cannot read '" + path + "': read error");
    return bytes;
}

std::vector<std::string> save_mip_chain(const std::string& path, const vqtex_image* levels, uint32_t count) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error("cannot write '" + path + "': unknown image format for this extension");
    std::vector<std::string> written;
    if (out->supports("mipmap")) {
        const std::string tmp = temporary_name_for(path);
        track(tmp);
        bool ok = true;
        for (uint32_t i = 0; i < count && ok; ++i) {
            OIIO::ImageSpec spec(int(levels[i].width), int(levels[i].height), int(levels[i].channels),
                                 OIIO::TypeDesc::UINT8);
            ok = out->open(tmp, spec, i == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel) &&
                 out->write_image(OIIO::TypeDesc::UINT8, levels[i].pixels);
        }
        ok = ok && out->close();
        commit_temporary(tmp, path, ok, ok ? "" : out->geterror());
        written.push_back(path);
        return written;
    }
    // Every level is written under a temporary name first, and only then
    // are they renamed into place: a failure while writing leaves every
    // existing file as it was.
    const fs::path p(path);
    std::vector<std::string> temporaries;
    try {
        for (uint32_t i = 0; i < count; ++i) {
            const std::string name = i == 0 ? path
                                            : (p.parent_path() / (p.stem().string() + "_mip" + std::to_string(i) +
                                                                  p.extension().string()))
                                                  .string();
            temporaries.push_back(
                write_temporary(name, levels[i].width, levels[i].height, levels[i].channels, levels[i].pixels));
            written.push_back(name);
        }
        for (std::size_t i = 0; i < written.size(); ++i) {
            commit_temporary(temporaries[i], written[i], true, "");
            temporaries[i].clear();
        }
    } catch (...) {
        std::error_code ec;
        for (const auto& t : temporaries)
            if (!t.empty()) fs::remove(t, ec);
        throw;
    }
    return written;
}

void save_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    const std::string tmp = temporary_name_for(path);
    track(tmp);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) untrack(tmp);
    if (!f) throw std::runtime_error("cannot write '" + path + "': cannot create a file in its folder");
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    commit_temporary(tmp, path, written && closed, "write failed (disk full?)");
}

}  // namespace vqtex_tools
