// A material set of the benchmarks: the PNG maps of one folder, each
// map's kind by vqtex-encode's naming rule, and each map's share of a set
// file's bytes. Shared by vqtex-bench's materials protocol and
// material-seeds, so that both load, name and share a set alike.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_images.hpp"
#include "material_stats.hpp"
#include "vqtex/vqtex.h"

namespace vqtex_tools {

// One map of a set: its name (the file's stem), its kind, its example (as
// encoded: reduced with --material-side) and the example's luminance.
struct ExampleMap {
    std::string name;
    vqtex_map_kind kind = VQTEX_MAP_DATA;
    Image image;
    std::vector<double> luma;
};

struct MaterialSet {
    std::string name;
    std::vector<ExampleMap> maps;  // colour maps first, then normal maps, then data, each by name
    int colour = -1, normal = -1;  // the first of each kind (the lit image), -1 when absent
    Shading shading;               // the example normal map's
};

// A map's kind from its name, by vqtex-encode's rule (docs/PROGRAMS.md,
// "--map"): normal... and nrm... are normal maps, the usual names of a
// colour map colour, anything else data (gloss, roughness, height).
vqtex_map_kind kind_of(const std::string& name);

// Reads a set's PNG maps, reduced to --material-side. Throws with the
// reason (a file that does not read, maps of different sizes).
MaterialSet load_set(const std::filesystem::path& folder, uint32_t side);

// Each map's share of a set file: the bytes of its coded atlas
// (vqtex_inspect's maps[i].bytes) plus the rest of the file (header, the
// guide's weights, synthesis parameters, checksum) split in proportion to
// those bytes, the rounding left to the last map so that the shares add up
// to the file. Throws vqtex_cpp::Error when the file does not inspect.
std::vector<std::size_t> shares_of(const std::vector<uint8_t>& file, const MaterialSet& set);

}  // namespace vqtex_tools
