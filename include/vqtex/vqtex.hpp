// vqtex.hpp - a thin C++ layer over vqtex.h: RAII images and exceptions
// carrying the status. Adds no behaviour.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "vqtex.h"

namespace vqtex_cpp {

class Error : public std::runtime_error {
public:
    explicit Error(const vqtex_error& e)
        : std::runtime_error(e.detail[0] ? e.detail : vqtex_status_message(e.status)),
          status_(e.status) {}
    vqtex_status status() const { return status_; }

private:
    vqtex_status status_;
};

// Owns a vqtex_image the library allocated.
class Image {
public:
    Image() = default;
    explicit Image(vqtex_image raw) : raw_(raw) {}
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;
    Image(Image&& o) noexcept : raw_(std::exchange(o.raw_, vqtex_image{})) {}
    Image& operator=(Image&& o) noexcept {
        if (this != &o) {
            vqtex_image_free(&raw_);
            raw_ = std::exchange(o.raw_, vqtex_image{});
        }
        return *this;
    }
    ~Image() { vqtex_image_free(&raw_); }

    const vqtex_image& get() const { return raw_; }
    vqtex_image* out() {
        vqtex_image_free(&raw_);
        return &raw_;
    }
    uint32_t width() const { return raw_.width; }
    uint32_t height() const { return raw_.height; }
    uint32_t channels() const { return raw_.channels; }
    const uint8_t* data() const { return raw_.pixels; }
    size_t size_bytes() const { return size_t(raw_.width) * raw_.height * raw_.channels; }

private:
    vqtex_image raw_{};
};

// Owns a vqtex_image16 the library allocated.
class Image16 {
public:
    Image16() = default;
    explicit Image16(vqtex_image16 raw) : raw_(raw) {}
    Image16(const Image16&) = delete;
    Image16& operator=(const Image16&) = delete;
    Image16(Image16&& o) noexcept : raw_(std::exchange(o.raw_, vqtex_image16{})) {}
    Image16& operator=(Image16&& o) noexcept {
        if (this != &o) {
            vqtex_image16_free(&raw_);
            raw_ = std::exchange(o.raw_, vqtex_image16{});
        }
        return *this;
    }
    ~Image16() { vqtex_image16_free(&raw_); }

    const vqtex_image16& get() const { return raw_; }
    uint32_t width() const { return raw_.width; }
    uint32_t height() const { return raw_.height; }
    uint32_t channels() const { return raw_.channels; }
    const uint16_t* data() const { return raw_.pixels; }
    size_t samples() const { return size_t(raw_.width) * raw_.height * raw_.channels; }

private:
    vqtex_image16 raw_{};
};

inline void check(vqtex_status status, const vqtex_error& error) {
    if (status != VQTEX_OK) {
        vqtex_error e = error;
        e.status = status;
        throw Error(e);
    }
}

inline Image synthesize(const vqtex_synth_params& params, const vqtex_image& example,
                        vqtex_synth_stats* stats = nullptr) {
    Image out;
    vqtex_error err{};
    check(vqtex_synthesize(&params, &example, out.out(), stats, &err), err);
    return out;
}

// Owns a buffer the library allocated (an encoded file).
class Buffer {
public:
    Buffer() = default;
    Buffer(uint8_t* data, size_t size) : data_(data), size_(size) {}
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    Buffer(Buffer&& o) noexcept : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)) {}
    Buffer& operator=(Buffer&& o) noexcept {
        if (this != &o) {
            vqtex_free(data_);
            data_ = std::exchange(o.data_, nullptr);
            size_ = std::exchange(o.size_, 0);
        }
        return *this;
    }
    ~Buffer() { vqtex_free(data_); }
    const uint8_t* data() const { return data_; }
    size_t size() const { return size_; }

private:
    uint8_t* data_ = nullptr;
    size_t size_ = 0;
};

inline Buffer encode(const vqtex_encode_params& params, const vqtex_image& example,
                     vqtex_encode_stats* stats = nullptr) {
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    check(vqtex_encode(&params, &example, &data, &size, stats, &err), err);
    return Buffer(data, size);
}

inline Image decode(const vqtex_decode_params& params, const uint8_t* data, size_t size) {
    Image out;
    vqtex_error err{};
    check(vqtex_decode(&params, data, size, out.out(), &err), err);
    return out;
}

// A decoded map of a set: its name, kind and pixels (owned): `image` for
// 8 bits, `image16` for a map kept at 12 bits.
struct Map {
    std::string name;
    vqtex_map_kind kind = VQTEX_MAP_COLOUR;
    uint32_t bits = 8;
    Image image;
    Image16 image16;
};

inline Buffer encode_maps(const vqtex_encode_params& params, const std::vector<vqtex_map>& maps,
                          vqtex_encode_stats* stats = nullptr) {
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    check(vqtex_encode_maps(&params, maps.data(), uint32_t(maps.size()), &data, &size, stats, &err), err);
    return Buffer(data, size);
}

inline std::vector<Map> decode_maps(const vqtex_decode_params& params, const uint8_t* data, size_t size) {
    std::vector<vqtex_map_image> raw(VQTEX_MAX_MAPS);
    uint32_t count = 0;
    vqtex_error err{};
    const vqtex_status st = vqtex_decode_maps(&params, data, size, raw.data(), uint32_t(raw.size()), &count, &err);
    std::vector<Map> out(count);
    for (uint32_t i = 0; i < count; ++i) {  // owned before any throw
        out[i].name = raw[i].name;
        out[i].kind = raw[i].kind;
        out[i].bits = raw[i].bits;
        out[i].image = Image(raw[i].image);
        out[i].image16 = Image16(raw[i].image16);
    }
    check(st, err);
    return out;
}

inline vqtex_file_info inspect(const uint8_t* data, size_t size, uint64_t memory_limit = 0) {
    vqtex_file_info info{};
    vqtex_error err{};
    check(vqtex_inspect(data, size, memory_limit, &info, &err), err);
    return info;
}

// Hole filling (paper section 5.1); example may be null.
inline Image fill(const vqtex_fill_params& params, const vqtex_image& image, const vqtex_image& mask,
                  const vqtex_image* example = nullptr, vqtex_fill_stats* stats = nullptr) {
    Image out;
    vqtex_error err{};
    check(vqtex_fill(&params, &image, &mask, example, out.out(), stats, &err), err);
    return out;
}

// Extrapolation: image placed at (x, y) in a width x height canvas; mask may be null.
inline Image extend(const vqtex_fill_params& params, const vqtex_image& image, uint32_t width,
                    uint32_t height, uint32_t x, uint32_t y, const vqtex_image* mask = nullptr,
                    const vqtex_image* example = nullptr, vqtex_fill_stats* stats = nullptr) {
    Image out;
    vqtex_error err{};
    check(vqtex_extend(&params, &image, mask, width, height, x, y, example, out.out(), stats, &err), err);
    return out;
}

// Owns a vqtex_volume the library allocated (an animation).
class Volume {
public:
    Volume() = default;
    Volume(const Volume&) = delete;
    Volume& operator=(const Volume&) = delete;
    Volume(Volume&& o) noexcept : raw_(std::exchange(o.raw_, vqtex_volume{})) {}
    Volume& operator=(Volume&& o) noexcept {
        if (this != &o) {
            vqtex_volume_free(&raw_);
            raw_ = std::exchange(o.raw_, vqtex_volume{});
        }
        return *this;
    }
    ~Volume() { vqtex_volume_free(&raw_); }

    const vqtex_volume& get() const { return raw_; }
    vqtex_volume* out() {
        vqtex_volume_free(&raw_);
        return &raw_;
    }
    uint32_t width() const { return raw_.width; }
    uint32_t height() const { return raw_.height; }
    uint32_t frames() const { return raw_.frames; }
    uint32_t channels() const { return raw_.channels; }
    size_t frame_bytes() const { return size_t(raw_.width) * raw_.height * raw_.channels; }
    const uint8_t* frame(uint32_t t) const { return raw_.pixels + frame_bytes() * t; }

private:
    vqtex_volume raw_{};
};

inline Buffer encode_volume(const vqtex_volume_encode_params& params, const vqtex_volume& example,
                            vqtex_encode_stats* stats = nullptr) {
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    check(vqtex_encode_volume(&params, &example, &data, &size, stats, &err), err);
    return Buffer(data, size);
}

inline Volume decode_volume(const vqtex_decode_params& params, uint32_t frames, const uint8_t* data, size_t size) {
    Volume out;
    vqtex_error err{};
    check(vqtex_decode_volume(&params, frames, data, size, out.out(), &err), err);
    return out;
}

inline Volume synthesize_volume(const vqtex_synth_params& params, const vqtex_volume& example, uint32_t frames = 0,
                                vqtex_synth_stats* stats = nullptr) {
    Volume out;
    vqtex_error err{};
    check(vqtex_synthesize_volume(&params, &example, frames, out.out(), stats, &err), err);
    return out;
}

}  // namespace vqtex_cpp
