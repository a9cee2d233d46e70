// atlas_coder.cpp - decoding the atlas bitstream of formats 3 to 8 with
// dav1d (docs/FORMAT.md §3). Every failure of dav1d, and every
// frame that is not exactly the one the section announces, is a CORRUPT
// file; dav1d's frame size limit is set to the announced size so a hostile
// bitstream cannot make it allocate more than the atlas.
#include "format/atlas_coder.hpp"

#include <dav1d/dav1d.h>

#include <algorithm>
#include <cerrno>
#include <functional>
#include <memory>

#include "common/bitstream.hpp"
#include "common/error.hpp"

namespace vqtex {

namespace {

// The product of 16-bit fixed-point coefficients and a centred chroma value,
// rounded to nearest with ties up: floor((c * v + 32768) / 65536). C++20
// defines >> of a negative value as the floor.
int fixed_mul(int c, int v) { return (c * v + 32768) >> 16; }

uint8_t clamp_byte(int v) { return uint8_t(std::clamp(v, 0, 255)); }

struct DecoderCloser {
    void operator()(Dav1dContext* c) const { dav1d_close(&c); }
};
struct PictureUnref {
    void operator()(Dav1dPicture* p) const {
        dav1d_picture_unref(p);
        delete p;
    }
};
using PicturePtr = std::unique_ptr<Dav1dPicture, PictureUnref>;

// The data is the caller's; dav1d only borrows it for the call.
void keep_buffer(const uint8_t*, void*) {}

[[noreturn]] void bad_bitstream(const std::string& where, const std::string& detail) {
    fail(VQTEX_ERROR_CORRUPT, where + ": " + detail);
}

// Every shown frame of an AV1 sequence, each exactly width x height at
// `bits`, handed to `take_frame` in display order; the sequence must hold
// exactly `frames` of them. dav1d runs on one thread, applies no film grain
// and outputs only shown frames of operating point 0: its output is then
// the frames the AV1 specification defines, on any platform. A still atlas
// is a sequence of one frame; an animation's atlas (format version 12) a
// sequence of its frames with inter prediction.
void decode_frames(const uint8_t* data, std::size_t size, int width, int height, int frames,
                   const std::string& where, int bits, const std::function<void(PicturePtr, int)>& take_frame) {
    if (size == 0) bad_bitstream(where, "the AV1 bitstream is empty");
    Dav1dSettings s;
    dav1d_default_settings(&s);
    s.n_threads = 1;
    s.max_frame_delay = 1;
    s.apply_grain = 0;
    s.all_layers = 0;
    s.operating_point = 0;
    s.frame_size_limit = unsigned(width) * unsigned(height);
    s.strict_std_compliance = 1;
    s.logger.callback = nullptr;  // no messages on stderr: errors come back as statuses
    Dav1dContext* raw = nullptr;
    if (const int res = dav1d_open(&raw, &s); res < 0) {
        if (res == DAV1D_ERR(ENOMEM)) fail(VQTEX_ERROR_OUT_OF_MEMORY, where + ": dav1d could not start");
        fail(VQTEX_ERROR_INTERNAL, where + ": dav1d could not start (" + std::to_string(res) + ")");
    }
    std::unique_ptr<Dav1dContext, DecoderCloser> ctx(raw);
    Dav1dData in{};
    if (dav1d_data_wrap(&in, data, size, keep_buffer, nullptr) < 0)
        fail(VQTEX_ERROR_OUT_OF_MEMORY, where + ": dav1d could not take the bitstream");
    struct DataUnref {
        Dav1dData* d;
        ~DataUnref() { dav1d_data_unref(d); }
    } unref{&in};
    int pictures = 0;
    auto take = [&](int res) {
        if (res == DAV1D_ERR(EAGAIN)) return false;
        if (res == DAV1D_ERR(ENOMEM)) fail(VQTEX_ERROR_OUT_OF_MEMORY, where + ": dav1d ran out of memory");
        if (res < 0)
            bad_bitstream(where, "the AV1 bitstream does not decode (dav1d error " + std::to_string(-res) + ")");
        return true;
    };
    // Each picture is checked and handed over as it comes, so only dav1d's
    // reference frames are held, whatever the sequence's length.
    const auto deliver = [&](PicturePtr p) {
        if (pictures >= frames)
            bad_bitstream(where, "the AV1 bitstream holds more than " + std::to_string(frames) +
                                     (frames == 1 ? " frame" : " frames"));
        const Dav1dPictureParameters& pp = p->p;
        if (pp.w != width || pp.h != height)
            bad_bitstream(where, "the AV1 frame is " + std::to_string(pp.w) + "x" + std::to_string(pp.h) +
                                     ", the file announces " + std::to_string(width) + "x" + std::to_string(height));
        if (pp.bpc != bits)
            bad_bitstream(where, "the AV1 frame has " + std::to_string(pp.bpc) + " bits per sample, not " +
                                     std::to_string(bits));
        take_frame(std::move(p), pictures++);
    };
    // The loop of dav1d.h: send what is left, collect pictures, then drain.
    for (int rounds = 0;; ++rounds) {
        take(dav1d_send_data(ctx.get(), &in));
        PicturePtr p(new Dav1dPicture{});
        // An empty picture struct when none came: nothing for
        // dav1d_picture_unref to free.
        if (take(dav1d_get_picture(ctx.get(), p.get()))) deliver(std::move(p));
        if (in.sz == 0) break;
        // dav1d consumes at least one OBU per call; a stream of n bytes
        // cannot need more than n rounds.
        if (rounds > int(std::min<std::size_t>(size, 1u << 20))) bad_bitstream(where, "dav1d made no progress");
    }
    for (;;) {
        PicturePtr p(new Dav1dPicture{});
        if (!take(dav1d_get_picture(ctx.get(), p.get()))) break;
        deliver(std::move(p));
    }
    if (pictures != frames)
        bad_bitstream(where, "the AV1 bitstream holds " + std::to_string(pictures) + " frames, not " +
                                 std::to_string(frames));
}

// The one frame of a still atlas's part.
PicturePtr decode_frame(const uint8_t* data, std::size_t size, int width, int height, const std::string& where,
                        int bits = 8) {
    PicturePtr picture;
    decode_frames(data, size, width, height, 1, where, bits, [&](PicturePtr p, int) { picture = std::move(p); });
    return picture;
}

// Where an atlas bitstream's colour frame lies: the whole bitstream, or
// with alpha after its size varint, with the alpha frame after it.
struct ColourPart {
    std::size_t at = 0, size = 0;
};
ColourPart colour_part(const uint8_t* data, std::size_t size, bool alpha, const std::string& where) {
    if (!alpha) return {0, size};
    ByteReader r(data, size, where);
    ColourPart part;
    part.size = std::size_t(r.varint_in("colour bitstream size", 1, size));
    part.at = r.position();
    if (part.size >= size - part.at) r.corrupt("no room left for the alpha bitstream");
    return part;
}

}  // namespace

void atlas_rgb_to_ycbcr(const uint8_t* rgb, uint8_t& y, uint8_t& cb, uint8_t& cr) {
    const int r = rgb[0], g = rgb[1], b = rgb[2];
    y = clamp_byte((19595 * r + 38470 * g + 7471 * b + 32768) >> 16);
    cb = clamp_byte(128 + ((-11059 * r - 21709 * g + 32768 * b + 32768) >> 16));
    cr = clamp_byte(128 + ((32768 * r - 27439 * g - 5329 * b + 32768) >> 16));
}

void atlas_ycbcr_to_rgb(int y, int cb, int cr, uint8_t* rgb) {
    const int u = cb - 128, v = cr - 128;
    rgb[0] = clamp_byte(y + fixed_mul(91881, v));
    rgb[1] = clamp_byte(y - fixed_mul(22554, u) - fixed_mul(46802, v));
    rgb[2] = clamp_byte(y + fixed_mul(116130, u));
}

namespace {

void check_atlas_shape(int width, int height, int channels, const std::string& where) {
    if (width < 1 || height < 1 || width > kMaxAtlasSide || height > kMaxAtlasSide)
        bad_bitstream(where, "atlas size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range");
    if (channels < 1 || channels > 4) bad_bitstream(where, "an atlas has 1 to 4 channels");
}

// A colour part's decoded frame into the first colour_channels channels of
// `out`: grey as it is, YCbCr through atlas_ycbcr_to_rgb.
void take_colour(const Dav1dPicture& pic, int colour_channels, Image& out, const std::string& where) {
    const Dav1dPictureParameters& pp = pic.p;
    const int width = out.width, height = out.height;
    const auto* yp = static_cast<const uint8_t*>(pic.data[0]);
    if (colour_channels == 1) {
        if (pp.layout != DAV1D_PIXEL_LAYOUT_I400) bad_bitstream(where, "a grey atlas must be a monochrome AV1 frame");
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) out.at(x, y)[0] = yp[std::ptrdiff_t(y) * pic.stride[0] + x];
        return;
    }
    if (pp.layout == DAV1D_PIXEL_LAYOUT_I400) bad_bitstream(where, "a colour atlas cannot be a monochrome AV1 frame");
    // Chroma subsampling as the frame has it (4:4:4, 4:2:2 or 4:2:0); a
    // pixel takes the chroma sample that covers it (no filter).
    const int sx = pp.layout == DAV1D_PIXEL_LAYOUT_I444 ? 0 : 1;
    const int sy = pp.layout == DAV1D_PIXEL_LAYOUT_I420 ? 1 : 0;
    const auto* up = static_cast<const uint8_t*>(pic.data[1]);
    const auto* vp = static_cast<const uint8_t*>(pic.data[2]);
    for (int y = 0; y < height; ++y) {
        const uint8_t* yr = yp + std::ptrdiff_t(y) * pic.stride[0];
        const uint8_t* ur = up + std::ptrdiff_t(y >> sy) * pic.stride[1];
        const uint8_t* vr = vp + std::ptrdiff_t(y >> sy) * pic.stride[1];
        for (int x = 0; x < width; ++x) atlas_ycbcr_to_rgb(yr[x], ur[x >> sx], vr[x >> sx], out.at(x, y));
    }
}

// An alpha part's decoded frame into the last channel of `out`.
void take_alpha(const Dav1dPicture& pic, Image& out, const std::string& where) {
    if (pic.p.layout != DAV1D_PIXEL_LAYOUT_I400) bad_bitstream(where, "the alpha plane must be a monochrome AV1 frame");
    const auto* ap = static_cast<const uint8_t*>(pic.data[0]);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) out.at(x, y)[out.channels - 1] = ap[std::ptrdiff_t(y) * pic.stride[0] + x];
}

}  // namespace

Image decode_atlas(const uint8_t* data, std::size_t size, int width, int height, int channels,
                   const std::string& where) {
    return std::move(decode_atlas_frames(data, size, width, height, channels, 1, where)[0]);
}

std::vector<Image> decode_atlas_frames(const uint8_t* data, std::size_t size, int width, int height, int channels,
                                       int frames, const std::string& where) {
    check_atlas_shape(width, height, channels, where);
    if (frames < 1 || frames > kMaxAtlasFrames)
        bad_bitstream(where, "an atlas has 1 to " + std::to_string(kMaxAtlasFrames) + " frames");
    const bool alpha = channels == 2 || channels == 4;
    const int colour_channels = alpha ? channels - 1 : channels;
    const ColourPart part = colour_part(data, size, alpha, where);
    std::vector<Image> out(std::size_t(frames), Image(width, height, channels));
    decode_frames(data + part.at, part.size, width, height, frames, where, 8,
                  [&](PicturePtr p, int t) { take_colour(*p, colour_channels, out[std::size_t(t)], where); });
    if (alpha) {
        const std::size_t at = part.at + part.size;
        const std::string alpha_where = where + " (alpha)";
        decode_frames(data + at, size - at, width, height, frames, alpha_where, 8,
                      [&](PicturePtr p, int t) { take_alpha(*p, out[std::size_t(t)], alpha_where); });
    }
    return out;
}

Image16 decode_atlas_high(const uint8_t* data, std::size_t size, int width, int height, int channels, int bits,
                          const std::string& where) {
    check_atlas_shape(width, height, channels, where);
    if (bits != 10 && bits != 12) bad_bitstream(where, "a high bit depth atlas has 10 or 12 bits");
    const bool alpha = channels == 2 || channels == 4;
    const int colour_channels = alpha ? channels - 1 : channels;
    const ColourPart part = colour_part(data, size, alpha, where);
    const std::size_t colour_size = part.size, colour_at = part.at;
    Image16 out(width, height, channels);
    // The frame's planes as they are, one per channel from `first`: no
    // colour conversion at high bit depth (docs/FORMAT.md §3).
    const auto take_planes = [&](const Dav1dPicture& pic, int planes, int first) {
        for (int p = 0; p < planes; ++p) {
            const auto* base = static_cast<const uint8_t*>(pic.data[p]);
            const std::ptrdiff_t stride = pic.stride[p == 0 ? 0 : 1];
            for (int y = 0; y < height; ++y) {
                const auto* row = reinterpret_cast<const uint16_t*>(base + std::ptrdiff_t(y) * stride);
                for (int x = 0; x < width; ++x) out.at(x, y)[first + p] = row[x];
            }
        }
    };
    {
        const PicturePtr pic = decode_frame(data + colour_at, colour_size, width, height, where, bits);
        const Dav1dPixelLayout layout = pic->p.layout;
        if (colour_channels == 1 && layout != DAV1D_PIXEL_LAYOUT_I400)
            bad_bitstream(where, "a grey atlas must be a monochrome AV1 frame");
        if (colour_channels == 3 && layout != DAV1D_PIXEL_LAYOUT_I444)
            bad_bitstream(where, "a 3-channel atlas of high bit depth must be a 4:4:4 AV1 frame");
        take_planes(*pic, colour_channels, 0);
    }
    if (alpha) {
        const std::size_t at = colour_at + colour_size;
        const PicturePtr pic = decode_frame(data + at, size - at, width, height, where + " (alpha)", bits);
        if (pic->p.layout != DAV1D_PIXEL_LAYOUT_I400)
            bad_bitstream(where, "the alpha plane must be a monochrome AV1 frame");
        take_planes(*pic, 1, channels - 1);
    }
    return out;
}

}  // namespace vqtex
