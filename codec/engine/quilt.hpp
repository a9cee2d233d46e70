// quilt.hpp - the output laid out by image quilting (Efros & Freeman 2001,
// "Image quilting for texture synthesis and transfer", section 2) with the
// patch insertion cut of Kwatra, Schödl, Essa, Turk, Bobick 2003
// ("Graphcut textures", section 3), on the output torus.
//
// Square blocks of the example, each the one (among those within a
// tolerance of the best, picked by the seed) whose pixels agree best with
// what the blocks before it left in its overlap, are placed in raster order
// with a fixed overlap; a minimum cut then decides, pixel by pixel, where the
// new block shows and where the output stays as it was. Where the
// coherent engine's copies meet along the lines its coarse levels laid out,
// the blocks here meet wherever they agree: a cell, a brick or a plank is
// cut only where the example offers nothing that continues it. The blocks
// lie inside the example, never across its edge, so that a wrapping example
// is not shown again one period further on. The output's last blocks
// overlap its first ones across the torus, so it tiles.
//
// Every cost is an exact integer and each block's search runs over all the
// example's places (quilt_search.hpp), and blocks laid at the same time
// never meet, so the positions are the same for any thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// A near-best block is one whose overlap cost is at most this many percent
// above the best's (Efros & Freeman's 0.1).
inline constexpr int kQuiltTolerancePercent = 10;

// The least example side quilting works on.
inline constexpr int kMinQuiltSide = 16;

// The block side for an example of this size: half its shorter side, at
// most 64, a multiple of 4; 0 when the example is too small (below
// kMinQuiltSide).
int quilt_block(int example_width, int example_height);

// How an output is covered: blocks of `block` pixels (half the output's
// shorter side at most, at least 4 or the side), their overlap a quarter
// of the block, and `nx` x `ny` of them at even steps of about block -
// overlap: block i of a row starts at i * width / nx (i * height / ny for
// a column), so that the last one overlaps the first across the torus as
// much as any other pair does.
struct QuiltGrid {
    int block = 0, overlap = 0, nx = 0, ny = 0;
};
QuiltGrid quilt_grid(int block, int width, int height);

// The most blocks a decode lays at the same time (formats 20 and 21), and the bytes
// quilting holds beside the output for an example: the example's
// transforms, and for each of `workers` blocks laid at once a search and
// the block's graph (docs/FORMAT.md §2.8's memory check). quilt_positions
// lays as many at once as fit the memory it is given.
inline constexpr int kQuiltWorkers = 4;
uint64_t quilt_memory(int example_width, int example_height, int channels, int workers);

// The order blocks are laid in. Raster order (format 19) lays them one
// after the other: each row's first block meets the row above's last
// across the torus, so no two can be laid at once. Wavefront order
// (formats 20 and 21) lays block (i, j) at step i + 2j, rows in order within a
// step: a block then meets only blocks of earlier steps or later ones, and
// the blocks of a step, and of nearby steps, are laid at the same time on
// as many threads as there are.
enum class QuiltOrder { kRaster, kWavefront };
// How each block's cut is found (both give a minimum cut; among cuts of
// equal cost they may differ). The maximum flow (formats 19 and 20) keeps
// the fewest pixels old (min_cut.hpp); the planar cut (format 21) takes a
// shortest path in the dual of the block's grid (planar_cut.hpp), several
// times faster, and falls back to the maximum flow for a block whose new
// pixels are all inside it (the last block of the torus).
enum class QuiltCut { kMaxFlow, kPlanar };
// The blocks (j * nx + i) in the order they are laid.
std::vector<int> quilt_order(int nx, int ny, QuiltOrder order);

// The width x height torus of packed example positions
// (coherent_positions.hpp) laid out with blocks of `block` pixels.
// `progress` (may be empty) hears of the blocks laid, on the calling
// thread; false cancels (VQTEX_ERROR_CANCELLED). Blocks are laid as many
// at once, and searched by transforms (the faster) rather than directly
// (the same result), as fit `search_memory` bytes beside the output
// (quilt_memory).
std::vector<uint32_t> quilt_positions(const Image& example, int width, int height, int block, uint64_t seed,
                                      int threads,
                                      const std::function<bool(uint64_t done, uint64_t total)>& progress = {},
                                      uint64_t search_memory = UINT64_MAX, QuiltOrder order = QuiltOrder::kRaster,
                                      QuiltCut cut = QuiltCut::kMaxFlow);

}  // namespace vqtex
