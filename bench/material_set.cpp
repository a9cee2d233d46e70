// A material set of the benchmarks (see material_set.hpp).
#include "material_set.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "image_io.hpp"
#include "vqtex/vqtex.hpp"

namespace vqtex_tools {

vqtex_map_kind kind_of(const std::string& name) {
    std::string lower = name;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (lower.rfind("normal", 0) == 0 || lower.rfind("nrm", 0) == 0) return VQTEX_MAP_NORMAL;
    for (const char* colour : {"albedo", "diffuse", "basecolor", "base_color", "color", "colour", "emissive"})
        if (lower == colour) return VQTEX_MAP_COLOUR;
    return VQTEX_MAP_DATA;
}

MaterialSet load_set(const std::filesystem::path& folder, uint32_t side) {
    MaterialSet set;
    set.name = folder.filename().string();
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(folder))
        if (e.path().extension() == ".png") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    uint32_t width = 0, height = 0;  // the first map's, before the reduction
    for (const std::filesystem::path& f : files) {
        const LoadedImage img = load_image(f.string());
        if (set.maps.empty()) width = img.width, height = img.height;
        if (img.width != width || img.height != height)
            throw std::runtime_error(f.string() + " is not the size of " + set.maps[0].name +
                                     ".png: the maps of a set have one size");
        ExampleMap m;
        m.name = f.stem().string();
        m.kind = kind_of(m.name);
        m.image = Image{int(img.width), int(img.height), int(img.channels), img.pixels};
        if (m.kind == VQTEX_MAP_NORMAL && m.image.channels != 3)
            throw std::runtime_error(f.string() + " is a normal map but not RGB");
        if (side && (int(side) != m.image.width || int(side) != m.image.height)) {
            if (int(side) > m.image.width || int(side) > m.image.height)
                throw std::runtime_error(f.string() + " is smaller than --material-side " + std::to_string(side));
            // Reduced normals are shorter than 1; the decoder's are not.
            m.image = reduced(m.image, int(side), int(side));
            if (m.kind == VQTEX_MAP_NORMAL) m.image = renormalised(m.image);
        }
        set.maps.push_back(std::move(m));
    }
    // The file's order: the colour map first (vqtex_decode on a set gives
    // the first map), normals next, data last.
    std::stable_sort(set.maps.begin(), set.maps.end(),
                     [](const ExampleMap& a, const ExampleMap& b) { return a.kind < b.kind; });
    for (std::size_t i = 0; i < set.maps.size(); ++i) {
        ExampleMap& m = set.maps[i];
        m.luma = luminance(m.image);
        if (m.kind == VQTEX_MAP_COLOUR && set.colour < 0) set.colour = int(i);
        if (m.kind == VQTEX_MAP_NORMAL && set.normal < 0) {
            set.normal = int(i);
            set.shading = shading(m.image);
        }
    }
    return set;
}

std::vector<std::size_t> shares_of(const std::vector<uint8_t>& file, const MaterialSet& set) {
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    std::vector<uint64_t> atlas(set.maps.size(), 0);
    uint64_t coded = 0;
    for (uint32_t i = 0; i < info.map_count && i < VQTEX_MAX_MAPS; ++i)
        for (std::size_t m = 0; m < set.maps.size(); ++m)
            if (set.maps[m].name == info.maps[i].name) atlas[m] = info.maps[i].bytes, coded += info.maps[i].bytes;
    std::vector<std::size_t> shares(set.maps.size(), 0);
    const uint64_t rest = file.size() > coded ? file.size() - coded : 0;
    uint64_t given = 0;
    for (std::size_t m = 0; m + 1 < set.maps.size(); ++m) {
        shares[m] = std::size_t(atlas[m] + (coded ? rest * atlas[m] / coded : rest / set.maps.size()));
        given += shares[m];
    }
    shares.back() = std::size_t(file.size() - given);
    return shares;
}

}  // namespace vqtex_tools
