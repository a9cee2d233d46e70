// imageio_oiio.cpp - vqtex_imageio, the loadable module that reads and
// writes images through OpenImageIO for the programs (see
// imageio_module.hpp for why it is a module of its own). It knows nothing of
// temporary names or signals: image_io.cpp does the atomic part.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "imageio_module.hpp"

namespace {

using vqtex_tools::ImageLevel;
using vqtex_tools::LoadedImage;
using vqtex_tools::ReadOptions;
using vqtex_tools::SampleSpace;
using vqtex_tools::WriteOptions;
using vqtex_tools::WrittenImage;

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

// The sRGB transfer curve (IEC 61966-2-1) both ways, on 0..1: the samples
// of a colour image are on it; a float file holds linear light.
float srgb_to_linear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }
float linear_to_srgb(float v) { return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f; }

// How the samples of a file become the reader's: which channel is alpha,
// what is undone on the way, and into how many bits.
struct Reading {
    int channels = 0;
    int alpha = -1;            // a colour image's alpha channel, or -1
    bool unassociate = false;  // the file holds colour premultiplied by alpha: divide it out
    bool linear = false;       // float colour, linear light: put it on the sRGB curve
    bool via_float = false;    // read as float and converted here; else OpenImageIO converts
    uint32_t bits = 8;
};

Reading reading_of(const OIIO::ImageSpec& spec, const ReadOptions& options) {
    Reading r;
    r.channels = std::min(spec.nchannels, 4);
    const bool is_float = spec.format.is_floating_point();
    // Data has no alpha: its last channel is a value like the others, read
    // as the file holds it.
    if (options.space == SampleSpace::colour && spec.alpha_channel >= 0 && spec.alpha_channel < r.channels)
        r.alpha = spec.alpha_channel;
    r.unassociate = r.alpha >= 0 && holds_associated_alpha(spec);
    r.linear = is_float && options.space == SampleSpace::colour;
    r.via_float = is_float || r.unassociate;
    r.bits = options.keep_16 && spec.format.size() > 1 ? 16 : 8;
    return r;
}

// Float samples (`samples` of them, whole pixels) as `r` says, rounded to
// T's range as OpenImageIO rounds; returns how many were outside 0..1 by
// more than the rounding would have taken back (NaN among them): the
// clamping changed them.
template <typename T>
uint64_t quantise(const float* in, std::size_t samples, const Reading& r, T* out) {
    const float top = float(std::numeric_limits<T>::max());
    const float slack = 0.5f / top;
    const std::size_t channels = std::size_t(r.channels);
    uint64_t clamped = 0;
    for (std::size_t p = 0; p < samples; p += channels) {
        const float a = r.alpha >= 0 ? in[p + std::size_t(r.alpha)] : 1.0f;
        for (std::size_t c = 0; c < channels; ++c) {
            float v = in[p + c];
            if (int(c) != r.alpha) {
                if (r.unassociate && a > 0.0f) v /= a;
                if (r.linear) v = linear_to_srgb(v);  // negative stays negative, NaN NaN: clamped below
            }
            if (!(v >= -slack && v <= 1.0f + slack)) ++clamped;
            v = v >= 0.0f ? std::min(v, 1.0f) : 0.0f;
            out[p + c] = T(std::lround(v * top));
        }
    }
    return clamped;
}

// Rows [y0, y1) read as float and converted by `r` into `out`; adds the
// samples clamped to `clamped`. In float, so that colour under a small
// alpha keeps the precision the file has.
template <typename T>
bool read_rows_converted(OIIO::ImageInput& in, int subimage, int y0, int y1, const Reading& r, T* out,
                         uint64_t& clamped) {
    const std::size_t samples = std::size_t(in.spec().width) * std::size_t(y1 - y0) * std::size_t(r.channels);
    std::vector<float> rows(samples);
    if (!read_rows(in, subimage, y0, y1, r.channels, OIIO::TypeDesc::FLOAT, rows.data())) return false;
    clamped += quantise(rows.data(), samples, r, out);
    return true;
}

// Rows [y0, y1) of `img` (sized for them), as `r` says.
bool read_image_rows(OIIO::ImageInput& in, int subimage, int y0, int y1, const Reading& r, LoadedImage& img,
                     std::size_t first_sample, uint64_t& clamped) {
    if (r.bits == 16) {
        uint16_t* out = img.pixels16.data() + first_sample;
        return r.via_float ? read_rows_converted(in, subimage, y0, y1, r, out, clamped)
                           : read_rows(in, subimage, y0, y1, r.channels, OIIO::TypeDesc::UINT16, out);
    }
    uint8_t* out = img.pixels.data() + first_sample;
    return r.via_float ? read_rows_converted(in, subimage, y0, y1, r, out, clamped)
                       : read_rows(in, subimage, y0, y1, r.channels, OIIO::TypeDesc::UINT8, out);
}

// What the reader did to the file's samples, for the notice; empty when it
// kept them as they are.
std::string conversion_notice(const OIIO::ImageSpec& spec, const Reading& r, uint64_t clamped) {
    const std::string from = spec.format.c_str(), to = std::to_string(r.bits) + " bits";
    std::string n;
    if (r.linear)
        n = "converted " + from + " samples from linear light to " + to + " on the sRGB curve";
    else if (spec.format.is_floating_point())
        n = "converted " + from + " samples to " + to + " (values as they are)";
    else if (spec.format.size() > 1 && (r.bits == 8 || spec.format != OIIO::TypeDesc::UINT16))
        n = "converted " + from + " samples to " + to + " (rounded)";
    if (clamped)
        n += (n.empty() ? "" : "; ") + std::to_string(clamped) + " sample" + (clamped == 1 ? "" : "s") +
             " outside 0..1 clamped";
    return n;
}

LoadedImage read(const std::string& path, const ReadOptions& options) {
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
    const Reading r = reading_of(spec, options);
    LoadedImage img;
    img.width = uint32_t(spec.width);
    img.height = uint32_t(spec.height);
    img.channels = uint32_t(r.channels);
    img.bits = r.bits;
    // Strips of rows, the buffer growing with them: a header that declares
    // a huge image over a short (truncated or forged) body fails after
    // allocating about what the file really holds, not what it claims.
    const std::size_t row_samples = std::size_t(spec.width) * img.channels;
    const int strip = strip_rows(spec);
    uint64_t clamped = 0;
    for (int y = 0; y < spec.height; y += strip) {
        const int rows = std::min(strip, spec.height - y);
        const std::size_t end = (std::size_t(y) + std::size_t(rows)) * row_samples;
        if (r.bits == 16)
            img.pixels16.resize(end);
        else
            img.pixels.resize(end);
        if (!read_image_rows(*in, 0, spec.y + y, spec.y + y + rows, r, img, std::size_t(y) * row_samples, clamped)) {
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
    if (spec.nchannels > 4) img.notice = "kept the first 4 of " + std::to_string(spec.nchannels) + " channels";
    const std::string converted = conversion_notice(spec, r, clamped);
    if (!converted.empty()) img.notice += (img.notice.empty() ? "" : "; ") + converted;
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

// Formats of floating-point samples, which by convention hold linear light
// (OpenEXR, Radiance HDR): colour goes off the sRGB curve into them.
bool holds_linear_float(const OIIO::ImageOutput& out) {
    const std::string format = out.format_name();
    return format == "openexr" || format == "hdr";
}

// The colour space the metadata names, in OpenImageIO 2.4's words ("sRGB",
// "Linear"; newer versions also say "lin_srgb" for the latter) and, for
// samples that are no colour, "Raw", as OpenColorIO configurations name
// such data.
const char* colour_space_name(SampleSpace space, bool linear_float) {
    if (space != SampleSpace::colour) return "Raw";
    return linear_float ? "Linear" : "sRGB";
}

// Channel names and the alpha channel: grey+alpha and RGBA colour have
// alpha last (OpenImageIO's default names a 2-channel image R, G, without
// alpha); data has none, whatever its channels.
void name_channels(OIIO::ImageSpec& spec, SampleSpace space) {
    spec.alpha_channel = -1;
    if (spec.nchannels == 1) spec.channelnames = {"Y"};
    if (space == SampleSpace::positions && spec.nchannels == 2) spec.channelnames = {"x", "y"};
    if (space == SampleSpace::colour && spec.nchannels == 2) {
        spec.channelnames = {"Y", "A"};
        spec.alpha_channel = 1;
    }
    if (space == SampleSpace::colour && spec.nchannels == 4) spec.alpha_channel = 3;
}

// A level's samples as a linear float file holds them: colour off the sRGB
// curve (alpha as it is) and, where `premultiply`, multiplied by alpha;
// data as value / max; positions as the numbers themselves.
std::vector<float> linear_samples(const ImageLevel& level, SampleSpace space, int alpha, bool premultiply) {
    const bool deep = level.pixels16 != nullptr;
    const std::size_t channels = level.channels;
    const std::size_t count = std::size_t(level.width) * level.height * channels;
    const float top = deep ? 65535.0f : 255.0f;
    // One entry per sample value: the curve costs a pow() per sample.
    std::vector<float> table(deep ? 65536 : 256);
    for (std::size_t i = 0; i < table.size(); ++i) {
        const float x = float(i);
        table[i] = space == SampleSpace::positions ? x : space == SampleSpace::data ? x / top : srgb_to_linear(x / top);
    }
    const auto sample = [&](std::size_t i) -> std::size_t { return deep ? level.pixels16[i] : level.pixels[i]; };
    std::vector<float> v(count);
    for (std::size_t p = 0; p < count; p += channels) {
        const float a = alpha >= 0 ? float(sample(p + std::size_t(alpha))) / top : 1.0f;
        for (std::size_t c = 0; c < channels; ++c) {
            const std::size_t s = sample(p + c);
            v[p + c] = int(c) == alpha ? a : premultiply ? table[s] * a : table[s];
        }
    }
    return v;
}

// The MIP levels of one file share a tile size; 64 is OpenEXR's and TIFF's
// usual one.
constexpr int kMipTile = 64;

WrittenImage write(const std::string& name, const std::string& file, const ImageLevel* levels, uint32_t count,
                   const WriteOptions& options, SampleSpace space) {
    auto out = output_for(name);
    const bool mip_tiff = count > 1 && is_tiff(*out);
    // 16-bit samples stay 16-bit (a format without them, such as JPEG,
    // takes 8); a float file gets half for 8-bit samples and float for
    // 16-bit ones, whose 12 bits half's 11 would not keep near 1.
    const bool deep = levels[0].pixels16 != nullptr;
    const bool linear_float = holds_linear_float(*out);
    const OIIO::TypeDesc file_type = linear_float ? (deep ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF)
                                                  : (deep ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
    WrittenImage written;
    written.colour_space = colour_space_name(space, linear_float);
    std::vector<OIIO::ImageSpec> specs;
    for (uint32_t i = 0; i < count; ++i) {
        OIIO::ImageSpec spec(int(levels[i].width), int(levels[i].height), int(levels[i].channels), file_type);
        name_channels(spec, space);
        // Only the PNG writer reads this; zlib's level decides most of a
        // PNG's write time (docs/PERFORMANCE.md, "Writing").
        spec.attribute("png:compressionLevel", options.png_compression);
        // PNG keeps it (as a text chunk, and "sRGB" also as its sRGB
        // chunk); TIFF keeps "sRGB" (Exif ColorSpace 1) and drops the rest.
        spec.attribute("oiio:ColorSpace", written.colour_space);
        if (linear_float) {
            // OpenImageIO 2.4 writes no "oiio:" attribute into an OpenEXR
            // header (and reads every one back as "Linear"): the header
            // says it itself, linear colour also by its Color Interop
            // Forum name, which newer OpenImageIO and Blender write.
            spec.attribute("vqtex:ColorSpace", written.colour_space);
            if (space == SampleSpace::colour) spec.attribute("colorInteropID", "lin_rec709_scene");
        }
        if (spec.alpha_channel >= 0 && !premultiplies_alpha(*out))
            spec.attribute("oiio:UnassociatedAlpha", 1);  // the pixels are straight: store them so
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
        if (ok && i == 0) written.samples = out->spec().format.c_str();  // what the format took
        if (ok && linear_float) {
            const std::vector<float> v =
                linear_samples(levels[i], space, specs[i].alpha_channel, premultiplies_alpha(*out));
            ok = out->write_image(OIIO::TypeDesc::FLOAT, v.data());
        } else if (ok && deep) {
            ok = out->write_image(OIIO::TypeDesc::UINT16, levels[i].pixels16);
        } else if (ok) {
            ok = out->write_image(OIIO::TypeDesc::UINT8, levels[i].pixels);
        }
    }
    ok = ok && out->close();
    if (!ok) {
        std::string why = one_line(out->geterror());
        throw std::runtime_error("cannot write '" + name + "': " + (why.empty() ? std::string("write failed") : why));
    }
    return written;
}

constexpr int kMaxSubimages = 65536;

int subimage_count(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return 0;
    int n = 1;
    while (n < kMaxSubimages && in->seek_subimage(n, 0)) ++n;
    return n;
}

// One subimage of a multi-image file as 8-bit colour, 1 to 4 channels (the
// frames of an animation, which the library takes in 8 bits).
LoadedImage read_subimage(OIIO::ImageInput& in, int index, const std::string& path) {
    if (!in.seek_subimage(index, 0))
        throw std::runtime_error("cannot read image " + std::to_string(index) + " of '" + path + "'");
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        throw std::runtime_error("image " + std::to_string(index) + " of '" + path + "' is not a 2D image");
    if (uint64_t(spec.width) * uint64_t(spec.height) > (uint64_t(1) << 28))
        throw std::runtime_error("image " + std::to_string(index) + " of '" + path + "' is too large");
    const Reading r = reading_of(spec, ReadOptions{});
    LoadedImage img;
    img.width = uint32_t(spec.width);
    img.height = uint32_t(spec.height);
    img.channels = uint32_t(r.channels);
    img.pixels.resize(std::size_t(img.width) * img.height * img.channels);
    uint64_t clamped = 0;
    const bool ok = r.via_float ? read_rows_converted(in, index, spec.y, spec.y + spec.height, r, img.pixels.data(),
                                                      clamped)
                                : in.read_image(index, 0, 0, r.channels, OIIO::TypeDesc::UINT8, img.pixels.data());
    if (!ok)
        throw std::runtime_error("cannot read image " + std::to_string(index) + " of '" + path +
                                 "': " + one_line(in.geterror()));
    img.notice = conversion_notice(spec, r, clamped);
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
