// image_io.cpp - image reading and atomic writing for the tools, through the
// OpenImageIO module that it loads on first use (imageio_module.hpp).
#include "image_io.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "imageio_module.hpp"
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

// Batches write several files at once.
std::mutex g_pending_mutex;

void track(const std::string& tmp) {
    install_cleanup_handlers();
    const std::lock_guard<std::mutex> lock(g_pending_mutex);
    for (int i = 0; i < kPendingSlots; ++i)
        if (!g_pending_used[i] && tmp.size() < sizeof g_pending[i]) {
            std::memcpy(g_pending[i], tmp.c_str(), tmp.size() + 1);
            g_pending_used[i] = 1;
            return;
        }
}

void untrack(const std::string& tmp) {
    const std::lock_guard<std::mutex> lock(g_pending_mutex);
    for (int i = 0; i < kPendingSlots; ++i)
        if (g_pending_used[i] && tmp == g_pending[i]) g_pending_used[i] = 0;
}

// Moves a finished temporary file into place; on failure removes it, so a
// failed write never leaves anything behind. Throws naming `path`.
// The temporary stays tracked until it is renamed or removed: a SIGTERM
// between the two would otherwise leave it behind (seen once in CI).
void commit_temporary(const std::string& tmp, const std::string& path, bool ok, const std::string& why) {
    std::error_code ec;
    if (!ok) {
        fs::remove(tmp, ec);
        untrack(tmp);
        throw std::runtime_error("cannot write '" + path + "': " + why);
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        const std::string message = ec.message();
        fs::remove(tmp, ec);
        untrack(tmp);
        throw std::runtime_error("cannot write '" + path + "': " + message);
    }
    untrack(tmp);
}

}  // namespace

namespace {

// QuietStderr's shared state (see image_io.hpp).
std::mutex g_stderr_mutex;
int g_quiet_depth = 0;
int g_real_stderr = -1;  // a duplicate of the real stderr while redirected
std::FILE* g_sink = nullptr;

}  // namespace

QuietStderr::QuietStderr() {
    const std::lock_guard<std::mutex> lock(g_stderr_mutex);
    if (g_quiet_depth++ > 0) return;
    std::fflush(stderr);
    g_sink = std::tmpfile();
    if (!g_sink) return;
    g_real_stderr = ::dup(2);
    if (g_real_stderr >= 0 && ::dup2(::fileno(g_sink), 2) < 0) {
        ::close(g_real_stderr);
        g_real_stderr = -1;
    }
}

QuietStderr::~QuietStderr() {
    const std::lock_guard<std::mutex> lock(g_stderr_mutex);
    if (--g_quiet_depth > 0) return;
    std::fflush(stderr);
    std::cerr.flush();
    if (g_real_stderr >= 0) {
        ::dup2(g_real_stderr, 2);
        ::close(g_real_stderr);
        g_real_stderr = -1;
    }
    if (g_sink) std::fclose(g_sink);
    g_sink = nullptr;
}

void write_stderr(const std::string& text) {
    const std::lock_guard<std::mutex> lock(g_stderr_mutex);
    std::fflush(stderr);
    const int fd = g_real_stderr >= 0 ? g_real_stderr : 2;
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n <= 0) break;
        done += std::size_t(n);
    }
}

namespace {

WriteOptions g_write_options;

// Finds and loads vqtex_imageio: VQTEX_IMAGEIO_MODULE when set, else beside
// the installed programs (BINDIR/../LIBDIR/vqtex), beside the program (the
// build tree) and where this build put it (tests and benchmarks, which live
// in folders of their own).
const ImageioModule* open_module() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("VQTEX_IMAGEIO_MODULE"); env && *env) {
        candidates.emplace_back(env);
    } else {
        std::error_code ec;
        const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec) {
            candidates.push_back((exe.parent_path() / VQTEX_IMAGEIO_FROM_BINDIR).lexically_normal().string());
            candidates.push_back((exe.parent_path() / VQTEX_IMAGEIO_FILE).string());
        }
        candidates.emplace_back(VQTEX_IMAGEIO_BUILD_PATH);
    }
    std::string tried;
    for (const std::string& path : candidates) {
        std::error_code ec;
        if (!fs::exists(path, ec)) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        // Lazy binding: functions of OpenImageIO's dependencies that no
        // call reaches are never resolved.
        void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
        if (!handle)
            throw std::runtime_error("image I/O module '" + path + "' cannot be loaded (" + ::dlerror() +
                                     "): is libopenimageio installed? (scripts/setup.sh)");
        using Entry = const ImageioModule* (*)();
        const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "vqtex_imageio_module"));
        const ImageioModule* module = entry ? entry() : nullptr;
        if (!module || module->abi != kImageioAbi)
            throw std::runtime_error("image I/O module '" + path +
                                     "' is from another build of vqtex: reinstall vqtex, or set VQTEX_IMAGEIO_MODULE");
        return module;
    }
    throw std::runtime_error("image I/O module " VQTEX_IMAGEIO_FILE " not found (looked for " + tried +
                             "): reinstall vqtex, or set VQTEX_IMAGEIO_MODULE to its path");
}

}  // namespace

const ImageioModule& imageio() {
    static const ImageioModule* const module = open_module();  // a throw leaves it to the next call
    return *module;
}

void load_image_io() { (void)imageio(); }

void set_write_options(const WriteOptions& options) { g_write_options = options; }

const WriteOptions& write_options() { return g_write_options; }

LoadedImage load_image(const std::string& path) { return load_image(path, ReadOptions{}); }

LoadedImage load_image(const std::string& path, const ReadOptions& options) {
    if (!fs::exists(path)) throw std::runtime_error("cannot read '" + path + "': no such file");
    if (fs::is_directory(path)) throw std::runtime_error("cannot read '" + path + "': it is a folder, not an image");
    const ImageioModule& io = imageio();
    const QuietStderr quiet;
    return io.read(path, options);
}

namespace {

// Writes an image to a temporary name beside `path` and returns that name;
// on failure removes it and throws naming `path`. `written` receives what
// the file holds.
std::string write_temporary(const std::string& path, const ImageLevel* levels, uint32_t count, SampleSpace space,
                            WrittenImage* written = nullptr) {
    const ImageioModule& io = imageio();
    const std::string tmp = temporary_name_for(path);
    track(tmp);
    try {
        const QuietStderr quiet;
        const WrittenImage w = io.write(path, tmp, levels, count, g_write_options, space);
        if (written) *written = w;
    } catch (...) {
        std::error_code ec;
        fs::remove(tmp, ec);
        untrack(tmp);
        throw;
    }
    return tmp;
}

}  // namespace

WrittenImage save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                        const uint8_t* pixels, SampleSpace space) {
    const ImageLevel level{width, height, channels, pixels, nullptr};
    WrittenImage written;
    commit_temporary(write_temporary(path, &level, 1, space, &written), path, true, "");
    return written;
}

WrittenImage save_image16(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                          const uint16_t* pixels, SampleSpace space) {
    const ImageLevel level{width, height, channels, nullptr, pixels};
    WrittenImage written;
    commit_temporary(write_temporary(path, &level, 1, space, &written), path, true, "");
    return written;
}

std::vector<uint8_t> load_bytes(const std::string& path, uint64_t max_bytes, const std::string& raise) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw std::runtime_error("cannot read '" + path + "': it is a folder");
    const auto too_large_error = [&] {
        return std::runtime_error("cannot read '" + path + "': it holds more than " + std::to_string(max_bytes) +
                                  " bytes, the most this tool reads" + (raise.empty() ? "" : " (" + raise + ")"));
    };
    if (fs::is_regular_file(path, ec)) {
        const uintmax_t size = fs::file_size(path, ec);
        if (!ec && size > max_bytes) throw too_large_error();
    }
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot read '" + path + "': " + (fs::exists(path) ? "permission denied" : "no such file"));
    std::vector<uint8_t> bytes;
    uint8_t buf[65536];
    std::size_t n;
    // Read in pieces and stop past the limit: a size from stat() is no
    // bound for pipes and devices.
    bool too_large = false;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
        if (uint64_t(bytes.size()) + n > max_bytes) {
            too_large = true;
            break;
        }
        bytes.insert(bytes.end(), buf, buf + n);
    }
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (too_large) throw too_large_error();
    if (failed) throw std::runtime_error("cannot read '" + path + "': read error");
    return bytes;
}

void refuse_folders(const std::vector<std::string>& names) {
    for (const std::string& name : names) {
        std::error_code ec;
        if (fs::is_directory(name, ec)) throw std::runtime_error("cannot write '" + name + "': it is a folder");
    }
}

std::vector<std::string> save_mip_chain(const std::string& path, const vqtex_image* levels, uint32_t count,
                                        SampleSpace space, WrittenImage* written_image) {
    std::vector<std::string> written;
    if (imageio().supports_mipmap(path)) {
        std::vector<ImageLevel> all;
        for (uint32_t i = 0; i < count; ++i)
            all.push_back(ImageLevel{levels[i].width, levels[i].height, levels[i].channels, levels[i].pixels, nullptr});
        commit_temporary(write_temporary(path, all.data(), count, space, written_image), path, true, "");
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
            const ImageLevel level{levels[i].width, levels[i].height, levels[i].channels, levels[i].pixels, nullptr};
            temporaries.push_back(write_temporary(name, &level, 1, space, i == 0 ? written_image : nullptr));
            written.push_back(name);
        }
        refuse_folders(written);
        for (std::size_t i = 0; i < written.size(); ++i) {
            commit_temporary(temporaries[i], written[i], true, "");
            temporaries[i].clear();
        }
    } catch (...) {
        std::error_code ec;
        for (const auto& t : temporaries)
            if (!t.empty()) {
                fs::remove(t, ec);
                untrack(t);
            }
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
