// container_writer.hpp - writing the vqtex file container of
// format/container.hpp (docs/FORMAT.md §B.1-§B.4): header, section
// table, payloads compressed with zstd where that helps, CRC-32 trailer.
#pragma once

#include <cstdint>
#include <vector>

#include "format/container.hpp"

namespace vqtex {

// Writing: sections are added with their raw bytes; write() compresses
// each (keeping it stored when zstd does not help) and assembles the file.
class ContainerWriter {
public:
    explicit ContainerWriter(const FileHeader& header, int zstd_level = 19)
        : header_(header), zstd_level_(zstd_level) {}
    void add(const char tag[4], uint8_t level, uint8_t kind, std::vector<uint8_t> raw);
    std::vector<uint8_t> write();

private:
    FileHeader header_;
    int zstd_level_;
    struct Pending {
        Section section;
        std::vector<uint8_t> raw;
    };
    std::vector<Pending> sections_;
};

}  // namespace vqtex
