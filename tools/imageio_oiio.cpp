// imageio_oiio.cpp - vqtex_imageio, the loadable module that reads and
// writes images through OpenImageIO for the programs (see
// imageio_module.hpp for why it is a module of its own). It knows nothing of
// temporary names or signals: image_io.cpp does the atomic part.
#include <algorithm>
#include <cmath>
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

// Alpha, in and out, is straight (unassociated): a texture keeps its colour
// under transparent pixels, which a mip filter or a later composite needs,
// and 8-bit colour premultiplied by a small alpha would keep only a few
// levels of it. OpenImageIO associates alpha on read unless told not to.
OIIO::ImageSpec straight_alpha_hint() {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

// Whether the opened image still holds associated alpha (a format that
// stores only that, such as OpenEXR, ignores the hint): the reader then
// divides it out.
bool holds_associated_alpha(const OIIO::ImageSpec& spec) {
    return spec.alpha_channel >= 0 && spec.alpha_channel < 4 && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0;
}

// Rows [y0, y1) of the first `channels` channels of `subimage`, in
// `format`. A tiled file is read by whole rows of tiles: OpenImageIO 2.4
// divides by zero reading scanlines of some tiled files (MIP-mapped TIFF
// and OpenEXR among them); `y0` is then a multiple of the tile height from
// the image's top, and `y1` one too or the image's bottom.
bool read_rows(OIIO::ImageInput& in, int subimage, int y0, int y1, int channels, OIIO::TypeDesc format, void* out) {
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.tile_width <= 0)
        return in.read_scanlines(subimage, 0, y0, y1, 0, 0, channels, format, out);
    return in.read_tiles(subimage, 0, spec.x, spec.x + spec.width, y0, y1, spec.z, spec.z + 1, 0, channels, format,
                         out);
}

// Rows per strip of a read: 64, rounded up to whole tiles for a tiled file.
int strip_rows(const OIIO::ImageSpec& spec) {
    constexpr int kStripRows = 64;
    if (spec.tile_width <= 0 || spec.tile_height <= 0) return kStripRows;
    return std::max(1, (kStripRows + spec.tile_height - 1) / spec.tile_height) * spec.tile_height;
}

// A float sample in 0..1 as 8 bits, rounded as OpenImageIO converts.
uint8_t to_8bit(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// Reads rows [y0, y1) of the first `channels` channels as 8-bit straight
// alpha into `out`, from a file that holds associated alpha: in float, so
// that colour under a small alpha keeps the precision the file has.
bool read_rows_unassociating(OIIO::ImageInput& in, int subimage, int y0, int y1, int channels, int alpha,
                             uint8_t* out) {
    const OIIO::ImageSpec& spec = in.spec();
    const std::size_t samples = std::size_t(spec.width) * std::size_t(y1 - y0) * std::size_t(channels);
    std::vector<float> rows(samples);
    if (!read_rows(in, subimage, y0, y1, channels, OIIO::TypeDesc::FLOAT, rows.data())) return false;
    for (std::size_t p = 0; p < samples; p += std::size_t(channels)) {
        const float a = rows[p + std::size_t(alpha)];
        for (int c = 0; c < channels; ++c) {
            const float v = rows[p + std::size_t(c)];
            out[p + std::size_t(c)] = to_8bit(c == alpha || a <= 0.0f ? v : v / a);
        }
    }
    return true;
}

LoadedImage read(const std::string& path) {
    const OIIO::ImageSpec hint = straight_alpha_hint();
    auto in = OIIO::ImageInput::open(path, &hint);
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
    const bool associated = holds_associated_alpha(spec);
    const int strip = strip_rows(spec);
    for (int y = 0; y < spec.height; y += strip) {
        const int rows = std::min(strip, spec.height - y);
        img.pixels.resize((std::size_t(y) + std::size_t(rows)) * row_bytes);
        uint8_t* const rows_out = img.pixels.data() + std::size_t(y) * row_bytes;
        const bool read_ok = associated ? read_rows_unassociating(*in, 0, spec.y + y, spec.y + y + rows, int(img.channels),
                                                                  spec.alpha_channel, rows_out)
                                        : read_rows(*in, 0, spec.y + y, spec.y + y + rows, int(img.channels),
                                                    OIIO::TypeDesc::UINT8, rows_out);
        if (!read_ok) {
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

// OpenImageIO writes MIP levels into one file for OpenEXR; TIFF holds them
// as reduced-resolution images after the first, read back as one MIP-mapped
// texture (what texture tools such as maketx write).
bool is_tiff(const OIIO::ImageOutput& out) { return std::string(out.format_name()) == "tiff"; }

bool supports_mipmap(const std::string& name) {
    const auto out = output_for(name);
    return out->supports("mipmap") != 0 || is_tiff(*out);
}

// OpenEXR stores colour premultiplied by alpha (its only convention), so a
// straight-alpha image is premultiplied on the way out, in float: halves
// keep colour under a small alpha that 8 bits would round away.
bool premultiplies_alpha(const OIIO::ImageOutput& out) { return std::string(out.format_name()) == "openexr"; }

std::vector<float> premultiplied(const ImageLevel& level, int alpha) {
    const std::size_t channels = level.channels;
    std::vector<float> v(std::size_t(level.width) * level.height * channels);
    for (std::size_t p = 0; p < v.size(); p += channels) {
        const float a = float(level.pixels[p + std::size_t(alpha)]) / 255.0f;
        for (std::size_t c = 0; c < channels; ++c) {
            const float x = float(level.pixels[p + c]) / 255.0f;
            v[p + c] = int(c) == alpha ? x : x * a;
        }
    }
    return v;
}

// The MIP levels of one file share a tile size; 64 is OpenEXR's and TIFF's
// usual one.
constexpr int kMipTile = 64;

void write(const std::string& name, const std::string& file, const ImageLevel* levels, uint32_t count,
           const WriteOptions& options) {
    auto out = output_for(name);
    const bool mip_tiff = count > 1 && is_tiff(*out);
    std::vector<OIIO::ImageSpec> specs;
    for (uint32_t i = 0; i < count; ++i) {
        OIIO::ImageSpec spec(int(levels[i].width), int(levels[i].height), int(levels[i].channels),
                             OIIO::TypeDesc::UINT8);
        // Only the PNG writer reads this; zlib's level decides most of a
        // PNG's write time (docs/PERFORMANCE.md, "Writing").
        spec.attribute("png:compressionLevel", options.png_compression);
        if (spec.alpha_channel >= 0) {
            if (premultiplies_alpha(*out))
                spec.set_format(OIIO::TypeDesc::HALF);
            else
                spec.attribute("oiio:UnassociatedAlpha", 1);  // the pixels are straight: store them so
        }
        if (count > 1) {
            spec.tile_width = kMipTile;
            spec.tile_height = kMipTile;
            // OpenEXR: a MIP-mapped file whose level sizes round up, as the
            // chain's do (pyramid levels keep odd edges).
            spec.attribute("openexr:levelmode", 1);
            spec.attribute("openexr:roundingmode", 1);
            // TIFF: marks the images after the first as its MIP levels.
            spec.attribute("textureformat", "Plain Texture");
        }
        specs.push_back(spec);
    }
    // A TIFF's images are declared up front; its first is then open.
    bool ok = !mip_tiff || out->open(file, int(count), specs.data());
    for (uint32_t i = 0; i < count && ok; ++i) {
        if (i == 0 && !mip_tiff)
            ok = out->open(file, specs[i], OIIO::ImageOutput::Create);
        else if (i > 0)
            ok = out->open(file, specs[i],
                           mip_tiff ? OIIO::ImageOutput::AppendSubimage : OIIO::ImageOutput::AppendMIPLevel);
        if (ok && specs[i].alpha_channel >= 0 && premultiplies_alpha(*out)) {
            const std::vector<float> v = premultiplied(levels[i], specs[i].alpha_channel);
            ok = out->write_image(OIIO::TypeDesc::FLOAT, v.data());
        } else if (ok) {
            ok = out->write_image(OIIO::TypeDesc::UINT8, levels[i].pixels);
        }
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
    const bool ok = holds_associated_alpha(spec)
                        ? read_rows_unassociating(in, index, spec.y, spec.y + spec.height, int(img.channels),
                                                  spec.alpha_channel, img.pixels.data())
                        : in.read_image(index, 0, 0, int(img.channels), OIIO::TypeDesc::UINT8, img.pixels.data());
    if (!ok)
        throw std::runtime_error("cannot read image " + std::to_string(index) + " of '" + path +
                                 "': " + one_line(in.geterror()));
    return img;
}

void read_subimages(const std::string& path, const std::function<void(LoadedImage&&)>& each) {
    const OIIO::ImageSpec hint = straight_alpha_hint();
    auto in = OIIO::ImageInput::open(path, &hint);
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
