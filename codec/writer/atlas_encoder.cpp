// atlas_encoder.cpp - libaom all-intra encoding of an atlas
// (docs/ATLAS.md): a still picture (g_limit = 1, so libaom writes the reduced
// still-picture sequence header, a few bytes), full-range YCbCr converted by
// atlas_rgb_to_ycbcr, one thread, raw OBUs without temporal delimiters.
#include "writer/atlas_encoder.hpp"

#include <aom/aom_encoder.h>
#include <aom/aomcx.h>

#include <algorithm>
#include <memory>
#include <string>

#include "common/bitstream.hpp"
#include "writer/byte_writer.hpp"
#include "common/error.hpp"
#include "format/atlas_coder.hpp"

namespace vqtex {

namespace {

struct CodecCloser {
    void operator()(aom_codec_ctx_t* c) const {
        aom_codec_destroy(c);
        delete c;
    }
};
struct ImageFree {
    void operator()(aom_image_t* i) const { aom_img_free(i); }
};

[[noreturn]] void aom_failed(aom_codec_ctx_t* c, const char* what) {
    const char* detail = c ? aom_codec_error_detail(c) : nullptr;
    fail(VQTEX_ERROR_INTERNAL, std::string("libaom: ") + what + " failed" + (detail ? std::string(": ") + detail : ""));
}

// One plane image to an AV1 frame; `planes` are the Y (or grey), Cb and Cr
// samples at full resolution (Cb, Cr empty for monochrome), 8 bits a
// sample, or `bits` (10 or 12) in 16-bit values, always 4:4:4 then.
// Planes of one frame: Y (or grey), Cb and Cr at full resolution, Cb and
// Cr empty for monochrome.
template <typename T>
struct FramePlanes {
    std::vector<T> luma, cb, cr;
};

// A sequence of frames to AV1: one frame is a still picture in all-intra
// mode; several are a key frame and inter frames (libaom's good-quality
// mode, with its look-ahead and hidden reference frames), every frame
// shown once in order.
template <typename T>
std::vector<uint8_t> encode_frames(int width, int height, const std::vector<FramePlanes<T>>& frames,
                                   const AtlasEncodeOptions& o, int bits = 8) {
    const bool mono = frames[0].cb.empty();
    const bool still = frames.size() == 1;
    const bool high = bits > 8;
    const bool full_chroma = (o.chroma444 || high) && !mono;
    aom_codec_iface_t* iface = aom_codec_av1_cx();
    aom_codec_enc_cfg_t cfg;
    if (aom_codec_enc_config_default(iface, &cfg, still ? AOM_USAGE_ALL_INTRA : AOM_USAGE_GOOD_QUALITY) !=
        AOM_CODEC_OK)
        aom_failed(nullptr, "default configuration");
    cfg.g_w = unsigned(width);
    cfg.g_h = unsigned(height);
    cfg.g_threads = 1;
    // One frame: a still picture, with the reduced still-picture header.
    // Several: one key frame, then inter frames predicted from up to 19
    // frames of look-ahead.
    cfg.g_limit = unsigned(frames.size());
    cfg.g_lag_in_frames = still ? 0 : unsigned(std::min<std::size_t>(frames.size(), 19));
    if (!still) {
        cfg.kf_mode = AOM_KF_DISABLED;
        cfg.kf_min_dist = cfg.kf_max_dist = unsigned(frames.size());
        cfg.g_timebase = {1, 30};
    }
    // AV1's profiles: main (0) 8 and 10 bits, 4:2:0 and monochrome; high
    // (1) 4:4:4 at those; professional (2) 12 bits.
    cfg.g_profile = bits == 12 ? 2 : full_chroma ? 1 : 0;
    cfg.g_bit_depth = bits == 12 ? AOM_BITS_12 : bits == 10 ? AOM_BITS_10 : AOM_BITS_8;
    cfg.g_input_bit_depth = unsigned(bits);
    cfg.monochrome = mono ? 1 : 0;
    cfg.rc_end_usage = AOM_Q;
    cfg.rc_min_quantizer = 0;
    cfg.rc_max_quantizer = 63;
    std::unique_ptr<aom_codec_ctx_t, CodecCloser> ctx;
    {
        auto* c = new aom_codec_ctx_t{};
        if (aom_codec_enc_init(c, iface, &cfg, high ? AOM_CODEC_USE_HIGHBITDEPTH : 0) != AOM_CODEC_OK) {
            const std::string detail = c->err_detail ? c->err_detail : "";
            delete c;
            fail(VQTEX_ERROR_INTERNAL, "libaom: encoder initialisation failed " + detail);
        }
        ctx.reset(c);
    }
    if (aom_codec_control(ctx.get(), AOME_SET_CPUUSED, o.speed) != AOM_CODEC_OK) aom_failed(ctx.get(), "speed");
    if (aom_codec_control(ctx.get(), AOME_SET_CQ_LEVEL, unsigned(o.cq_level)) != AOM_CODEC_OK)
        aom_failed(ctx.get(), "quality level");
    if (aom_codec_control(ctx.get(), AV1E_SET_COLOR_RANGE, int(AOM_CR_FULL_RANGE)) != AOM_CODEC_OK)
        aom_failed(ctx.get(), "colour range");
    if (aom_codec_control(ctx.get(), AV1E_SET_ROW_MT, 0u) != AOM_CODEC_OK) aom_failed(ctx.get(), "row threads");
    for (const auto& [id, value] : o.controls)
        if (aom_codec_control(ctx.get(), id, value) != AOM_CODEC_OK) aom_failed(ctx.get(), "control");

    const aom_img_fmt_t format = full_chroma ? AOM_IMG_FMT_I444 : AOM_IMG_FMT_I420;
    std::unique_ptr<aom_image_t, ImageFree> img(aom_img_alloc(
        nullptr, high ? aom_img_fmt_t(format | AOM_IMG_FMT_HIGHBITDEPTH) : format, unsigned(width), unsigned(height), 1));
    if (!img) fail(VQTEX_ERROR_OUT_OF_MEMORY, "libaom: no memory for the atlas image");
    img->range = AOM_CR_FULL_RANGE;
    img->monochrome = mono ? 1 : 0;
    if (high) img->bit_depth = unsigned(bits);
    // Samples of plane p at (x, y), strides in bytes.
    const auto sample = [&](int p, int x, int y) -> T& {
        return reinterpret_cast<T*>(img->planes[p] + std::ptrdiff_t(y) * img->stride[p])[x];
    };
    const T neutral = T(1 << (bits - 1));
    const auto fill = [&](const FramePlanes<T>& f) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) sample(0, x, y) = f.luma[std::size_t(y) * width + x];
        const int cw = full_chroma ? width : (width + 1) / 2, ch = full_chroma ? height : (height + 1) / 2;
        for (int p = 1; p <= 2; ++p) {
            const std::vector<T>* src = p == 1 ? &f.cb : &f.cr;
            for (int y = 0; y < ch; ++y)
                for (int x = 0; x < cw; ++x) {
                    T v = neutral;
                    if (mono) {
                    } else if (full_chroma) {
                        v = (*src)[std::size_t(y) * width + x];
                    } else {
                        // The mean of the 2x2 block (fewer at the right and
                        // bottom edges of odd sizes); the decoder replicates it.
                        int sum = 0, n = 0;
                        for (int dy = 0; dy < 2; ++dy)
                            for (int dx = 0; dx < 2; ++dx) {
                                const int sx = 2 * x + dx, sy = 2 * y + dy;
                                if (sx < width && sy < height) {
                                    sum += (*src)[std::size_t(sy) * width + sx];
                                    ++n;
                                }
                            }
                        v = T((sum + n / 2) / n);
                    }
                    sample(p, x, y) = v;
                }
        }
    };
    std::vector<uint8_t> out;
    auto collect = [&] {
        aom_codec_iter_t iter = nullptr;
        while (const aom_codec_cx_pkt_t* pkt = aom_codec_get_cx_data(ctx.get(), &iter))
            if (pkt->kind == AOM_CODEC_CX_FRAME_PKT) {
                const auto* b = static_cast<const uint8_t*>(pkt->data.frame.buf);
                out.insert(out.end(), b, b + pkt->data.frame.sz);
            }
    };
    for (std::size_t t = 0; t < frames.size(); ++t) {
        fill(frames[t]);
        if (aom_codec_encode(ctx.get(), img.get(), aom_codec_pts_t(t), 1, 0) != AOM_CODEC_OK)
            aom_failed(ctx.get(), "encoding");
        collect();
    }
    // Drain the look-ahead until the encoder has nothing left.
    for (;;) {
        const std::size_t before = out.size();
        if (aom_codec_encode(ctx.get(), nullptr, 0, 0, 0) != AOM_CODEC_OK) aom_failed(ctx.get(), "flushing");
        collect();
        if (out.size() == before) break;
    }
    return strip_temporal_delimiters(out);
}

}  // namespace

std::vector<uint8_t> strip_temporal_delimiters(const std::vector<uint8_t>& obus) {
    std::vector<uint8_t> out;
    ByteReader r(obus.data(), obus.size(), "libaom's output");
    while (r.remaining() > 0) {
        const std::size_t start = r.position();
        const uint8_t header = r.u8("OBU header");
        const int type = (header >> 3) & 15;
        if (header & 4) r.u8("OBU extension");
        if (!(header & 2)) fail(VQTEX_ERROR_INTERNAL, "libaom wrote an OBU without a size field");
        const uint64_t size = r.varint("OBU size");
        if (size > r.remaining()) fail(VQTEX_ERROR_INTERNAL, "libaom wrote an OBU that overruns its output");
        r.bytes(std::size_t(size), "OBU payload");
        if (type != kObuTemporalDelimiter) out.insert(out.end(), obus.begin() + std::ptrdiff_t(start),
                                                      obus.begin() + std::ptrdiff_t(r.position()));
    }
    return out;
}

namespace {

std::vector<uint8_t> encode_sequence(const std::vector<const Image*>& images, const AtlasEncodeOptions& options) {
    if (images.empty() || images.size() > std::size_t(kMaxAtlasFrames))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "an atlas has 1 to " + std::to_string(kMaxAtlasFrames) + " frames");
    const int w = images[0]->width, h = images[0]->height, c = images[0]->channels;
    if (w < 1 || h < 1 || w > kMaxAtlasSide || h > kMaxAtlasSide)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "atlas size " + std::to_string(w) + "x" + std::to_string(h) +
                                               " is out of range (1 to " + std::to_string(kMaxAtlasSide) + ")");
    if (c < 1 || c > 4) fail(VQTEX_ERROR_INVALID_ARGUMENT, "an atlas has 1 to 4 channels");
    if (options.cq_level < 0 || options.cq_level > 63 || options.speed < 0 || options.speed > 9)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "atlas quality level 0..63 and speed 0..9");
    for (const Image* image : images)
        if (image->width != w || image->height != h || image->channels != c)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "an atlas's frames must all have the first frame's size and channels");
    const std::size_t n = images[0]->pixel_count();
    const bool alpha = c == 2 || c == 4;
    std::vector<FramePlanes<uint8_t>> colour(images.size()), alphas(alpha ? images.size() : 0);
    for (std::size_t t = 0; t < images.size(); ++t) {
        FramePlanes<uint8_t>& f = colour[t];
        f.luma.resize(n);
        if (c >= 3) {
            f.cb.resize(n);
            f.cr.resize(n);
        }
        if (alpha) alphas[t].luma.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const uint8_t* p = images[t]->pixels.data() + i * std::size_t(c);
            if (c >= 3)
                atlas_rgb_to_ycbcr(p, f.luma[i], f.cb[i], f.cr[i]);
            else
                f.luma[i] = p[0];
            if (alpha) alphas[t].luma[i] = p[c - 1];
        }
    }
    std::vector<uint8_t> coded = encode_frames(w, h, colour, options);
    if (!alpha) return coded;
    ByteWriter out;
    out.varint(coded.size());
    out.bytes(coded);
    out.bytes(encode_frames(w, h, alphas, options));
    return std::move(out.data());
}

}  // namespace

std::vector<uint8_t> encode_atlas(const Image& image, const AtlasEncodeOptions& options) {
    return encode_sequence({&image}, options);
}

std::vector<uint8_t> encode_atlas_frames(const std::vector<Image>& frames, const AtlasEncodeOptions& options) {
    std::vector<const Image*> images;
    for (const Image& f : frames) images.push_back(&f);
    return encode_sequence(images, options);
}

std::vector<uint8_t> encode_atlas_high(const Image16& image, int bits, const AtlasEncodeOptions& options) {
    const int w = image.width, h = image.height, c = image.channels;
    if (w < 1 || h < 1 || w > kMaxAtlasSide || h > kMaxAtlasSide || c < 1 || c > 4 || (bits != 10 && bits != 12))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "a high bit depth atlas of 1 to " + std::to_string(kMaxAtlasSide) +
                                               " pixels a side, 1 to 4 channels, 10 or 12 bits");
    if (options.cq_level < 0 || options.cq_level > 63 || options.speed < 0 || options.speed > 9)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "atlas quality level 0..63 and speed 0..9");
    const std::size_t n = image.pixel_count();
    const bool alpha = c == 2 || c == 4;
    const int colour = alpha ? c - 1 : c;
    const uint16_t top = uint16_t((1 << bits) - 1);
    std::vector<std::vector<uint16_t>> planes(static_cast<std::size_t>(c), std::vector<uint16_t>(n));
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < c; ++k)
            planes[std::size_t(k)][i] = std::min(image.pixels[i * std::size_t(c) + std::size_t(k)], top);
    std::vector<FramePlanes<uint16_t>> colour_frame(1);
    colour_frame[0].luma = std::move(planes[0]);
    if (colour == 3) {
        colour_frame[0].cb = std::move(planes[1]);
        colour_frame[0].cr = std::move(planes[2]);
    }
    std::vector<uint8_t> frame = encode_frames(w, h, colour_frame, options, bits);
    if (!alpha) return frame;
    std::vector<FramePlanes<uint16_t>> alpha_frame(1);
    alpha_frame[0].luma = std::move(planes[std::size_t(c - 1)]);
    ByteWriter out;
    out.varint(frame.size());
    out.bytes(frame);
    out.bytes(encode_frames(w, h, alpha_frame, options, bits));
    return std::move(out.data());
}

}  // namespace vqtex
