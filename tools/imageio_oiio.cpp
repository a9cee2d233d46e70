// imageio_oiio.cpp - vqtex_imageio, the loadable module that reads and
// writes images through OpenImageIO for the programs (see
// imageio_module.hpp for why it is a module of its own). It knows nothing of
// temporary names or signals: image_io.cpp does the atomic part.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "imageio_module.hpp"

namespace {

using vqtex_tools::ImageLevel;
using vqtex_tools::LoadedImage;
using vqtex_tools::WriteOptions;

// OpenImageIO's errors may span lines (one per layer that saw them).
std::string one_line(std::string why) {
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    for (std::size_t at; (at = why.find('\n')) != std::string::npos;) why.replace(at, 1, "; ");
    return why;
}

std::vector<uint8_t> file_bytes(const std::string& path) {
    std::vector<uint8_t> bytes;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot read '" + path + "'");
    uint8_t buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
    std::fclose(f);
    return bytes;
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

LoadedImage read(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = one_line(OIIO::geterror());
        if (why.empty()) why = "not an image format OpenImageIO can read";
        throw std::runtime_error("cannot read '" + path + "': " + why);
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0)
        throw std::runtime_error("'" + path + "' has zero size (" + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) + ")");
    if (spec.depth > 1) throw std::runtime_error("'" + path + "' is a volume image; only 2D images are supported");
    const uint64_t pixels = uint64_t(spec.width) * uint64_t(spec.height);
    if (spec.width > 65536 || spec.height > 65536 || pixels > (uint64_t(1) << 30))
        throw std::runtime_error("'" + path + "' is " + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) + ", larger than the 65536-per-side, 2^30-pixel limit");
    LoadedImage img;
    img.width = uint32_t(spec.width);
    img.height = uint32_t(spec.height);
    img.channels = uint32_t(std::min(spec.nchannels, 4));
    if (spec.nchannels > 4) img.notice = "kept the first 4 of " + std::to_string(spec.nchannels) + " channels";
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
    if (std::string(in->format_name()) == "jpeg" && !jpeg_is_complete(file_bytes(path)))
        throw std::runtime_error("cannot decode '" + path +
                                 "': the JPEG data ends before its end-of-image marker: the file is truncated");
    in->close();
    return img;
}

std::unique_ptr<OIIO::ImageOutput> output_for(const std::string& name) {
    auto out = OIIO::ImageOutput::create(name);
    if (!out)
        throw std::runtime_error("cannot write '" + name + "': unknown image format for this extension (" +
                                 one_line(OIIO::geterror()) + ")");
    return out;
}

bool supports_mipmap(const std::string& name) { return output_for(name)->supports("mipmap") != 0; }

void write(const std::string& name, const std::string& file, const ImageLevel* levels, uint32_t count,
           const WriteOptions& options) {
    auto out = output_for(name);
    bool ok = true;
    for (uint32_t i = 0; i < count && ok; ++i) {
        OIIO::ImageSpec spec(int(levels[i].width), int(levels[i].height), int(levels[i].channels),
                             OIIO::TypeDesc::UINT8);
        // Only the PNG writer reads this; zlib's level decides most of a
        // PNG's write time (docs/PERFORMANCE.md, "Writing").
        spec.attribute("png:compressionLevel", options.png_compression);
        ok = out->open(file, spec, i == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel) &&
             out->write_image(OIIO::TypeDesc::UINT8, levels[i].pixels);
    }
    ok = ok && out->close();
    if (!ok) {
        std::string why = one_line(out->geterror());
        throw std::runtime_error("cannot write '" + name + "': " + (why.empty() ? std::string("write failed") : why));
    }
}

constexpr int kMaxSubimages = 65536;

int subimage_count(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return 0;
    int n = 1;
    while (n < kMaxSubimages && in->seek_subimage(n, 0)) ++n;
    return n;
}

// One subimage of a multi-image file as 8 bits, 1 to 4 channels.
LoadedImage read_subimage(OIIO::ImageInput& in, int index, const std::string& path) {
    if (!in.seek_subimage(index, 0))
        throw std::runtime_error("cannot read image " + std::to_string(index) + " of '" + path + "'");
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        throw std::runtime_error("image " + std::to_string(index) + " of '" + path + "' is not a 2D image");
    if (uint64_t(spec.width) * uint64_t(spec.height) > (uint64_t(1) << 28))
        throw std::runtime_error("image " + std::to_string(index) + " of '" + path + "' is too large");
    LoadedImage img;
    img.width = uint32_t(spec.width);
    img.height = uint32_t(spec.height);
    img.channels = uint32_t(std::min(spec.nchannels, 4));
    img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
    if (!in.read_image(index, 0, 0, int(img.channels), OIIO::TypeDesc::UINT8, img.pixels.data()))
        throw std::runtime_error("cannot read image " + std::to_string(index) + " of '" + path +
                                 "': " + one_line(in.geterror()));
    return img;
}

void read_subimages(const std::string& path, const std::function<void(LoadedImage&&)>& each) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error("cannot read '" + path + "': " + one_line(OIIO::geterror()));
    const int n = subimage_count(path);
    for (int i = 0; i < n; ++i) each(read_subimage(*in, i, path));
}

const vqtex_tools::ImageioModule kModule{vqtex_tools::kImageioAbi, read,           supports_mipmap,
                                         write,                    subimage_count, read_subimages};

}  // namespace

extern "C" __attribute__((visibility("default"))) const vqtex_tools::ImageioModule* vqtex_imageio_module() {
    return &kModule;
}
