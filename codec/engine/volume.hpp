// volume.hpp - frame stacks (x, y, t) and their 3D Gaussian pyramids for
// temporal textures (paper section 5.2: "the two Gaussian pyramids are
// constructed by filtering and downsampling from 3D volumetric data").
//
// A Volume keeps its frames stacked in one Image of width x (height * frames),
// frame t occupying rows t*height .. t*height+height-1, so the 2D helpers that
// see only a bag of pixels (histograms, matched noise) work on it unchanged.
// Level L+1 of a volume pyramid is level L filtered by the binomial
// [1 4 6 4 1]/16 along x, y and t and decimated by 2 along each (sizes round
// up), in exact integer arithmetic: (sum + 2048) >> 12, halves rounding up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "engine/pyramid.hpp"

namespace vqtex {

struct Volume {
    int width = 0;
    int height = 0;
    int frames = 0;
    int channels = 0;
    Image stack;  // width x (height * frames)

    Volume() = default;
    Volume(int w, int h, int t, int c) : width(w), height(h), frames(t), channels(c), stack(w, h * t, c) {}

    bool empty() const { return width == 0 || height == 0 || frames == 0; }
    std::size_t frame_pixels() const { return std::size_t(width) * std::size_t(height); }
    std::size_t voxel_count() const { return frame_pixels() * std::size_t(frames); }
    std::size_t byte_count() const { return voxel_count() * std::size_t(channels); }

    uint8_t* at(int x, int y, int t) { return stack.at(x, t * height + y); }
    const uint8_t* at(int x, int y, int t) const { return stack.at(x, t * height + y); }
    // Toroidal in x, y and t.
    const uint8_t* wrapped(int x, int y, int t) const {
        return at(Image::wrap(x, width), Image::wrap(y, height), Image::wrap(t, frames));
    }
    uint8_t* frame_data(int t) { return at(0, 0, t); }
    const uint8_t* frame_data(int t) const { return at(0, 0, t); }
    Image frame(int t) const;

    bool operator==(const Volume& o) const {
        return width == o.width && height == o.height && frames == o.frames && stack == o.stack;
    }
};

// Edge handling per axis: examples mirror in space and time unless they are
// tileable; synthesised volumes wrap in all three.
Volume downsample_volume(const Volume& volume, EdgeMode edges);

// [0] is the volume itself; each next level halves x, y and t (rounding up).
std::vector<Volume> build_volume_pyramid(const Volume& volume, int levels, EdgeMode edges);

}  // namespace vqtex
