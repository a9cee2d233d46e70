// image_io.cpp - OpenImageIO-backed image reading and atomic writing.
#include "image_io.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
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

// Moves a finished temporary file into place; on failure removes it, so a
// failed write never leaves anything behind. Throws naming `path`.
void commit_temporary(const std::string& tmp, const std::string& path, bool ok, const std::string& why) {
    std::error_code ec;
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

LoadedImage load_image(const std::string& path) {
    if (!fs::exists(path)) throw std::runtime_error("cannot read '" + path + "': no such file");
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
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
    img.pixels.resize(pixels * img.channels);
    if (!in->read_image(0, 0, 0, int(img.channels), OIIO::TypeDesc::UINT8, img.pixels.data())) {
        std::string why = in->geterror();
        throw std::runtime_error("cannot decode '" + path + "': " +
                                 (why.empty() ? std::string("read failed") : why));
    }
    in->close();
    return img;
}

void save_image(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                const uint8_t* pixels) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out)
        throw std::runtime_error("cannot write '" + path + "': unknown image format for this extension (" +
                                 OIIO::geterror() + ")");
    OIIO::ImageSpec spec(int(width), int(height), int(channels), OIIO::TypeDesc::UINT8);
    const std::string tmp = temporary_name_for(path);
    const bool ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels) && out->close();
    commit_temporary(tmp, path, ok, ok ? "" : out->geterror());
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
    const fs::path p(path);
    try {
        for (uint32_t i = 0; i < count; ++i) {
            const std::string name = i == 0 ? path
                                            : (p.parent_path() / (p.stem().string() + "_mip" + std::to_string(i) +
                                                                  p.extension().string()))
                                                  .string();
            save_image(name, levels[i].width, levels[i].height, levels[i].channels, levels[i].pixels);
            written.push_back(name);
        }
    } catch (...) {
        std::error_code ec;
        for (const auto& w : written) fs::remove(w, ec);
        throw;
    }
    return written;
}

void save_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    const std::string tmp = temporary_name_for(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write '" + path + "': cannot create a file in its folder");
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    commit_temporary(tmp, path, written && closed, "write failed (disk full?)");
}

}  // namespace vqtex_tools
