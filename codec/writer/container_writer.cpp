// container_writer.cpp - assembling a vqtex container (docs/FORMAT.md
// §B.1-§B.4) from raw sections.
#include "writer/container_writer.hpp"

#include <cstring>

#include "common/checksum.hpp"
#include "writer/byte_writer.hpp"
#include "writer/zstd_compress.hpp"

namespace vqtex {

void ContainerWriter::add(const char tag[4], uint8_t level, uint8_t kind, std::vector<uint8_t> raw) {
    Pending p;
    std::memcpy(p.section.tag.data(), tag, 4);
    p.section.level = level;
    p.section.kind = kind;
    p.section.raw_size = raw.size();
    p.raw = std::move(raw);
    sections_.push_back(std::move(p));
}

std::vector<uint8_t> ContainerWriter::write() {
    ByteWriter w;
    w.bytes(kMagic, sizeof kMagic);
    w.u16(header_.version);
    w.u16(header_.flags);
    w.u32(header_.exemplar_width);
    w.u32(header_.exemplar_height);
    w.u8(header_.channels);
    w.u8(header_.levels);
    w.u8(header_.init);
    w.u8(header_.backtrack);
    w.u64(header_.seed);
    w.u32(uint32_t(sections_.size()));
    w.u32(0);  // reserved
    std::vector<std::vector<uint8_t>> payloads;
    for (Pending& p : sections_) {
        std::vector<uint8_t> z = zstd_compress(p.raw, zstd_level_);
        if (z.size() < p.raw.size()) {
            p.section.coding = SectionCoding::Zstd;
            payloads.push_back(std::move(z));
        } else {
            p.section.coding = SectionCoding::Stored;
            payloads.push_back(std::move(p.raw));
        }
        p.section.stored_size = payloads.back().size();
    }
    for (std::size_t i = 0; i < sections_.size(); ++i) {
        const Section& s = sections_[i].section;
        w.bytes(reinterpret_cast<const uint8_t*>(s.tag.data()), 4);
        w.u8(s.level);
        w.u8(s.kind);
        w.u8(uint8_t(s.coding));
        w.u8(0);
        w.u32(uint32_t(s.raw_size));
        w.u32(uint32_t(s.stored_size));
        w.bytes(payloads[i]);
    }
    w.u32(crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

}  // namespace vqtex
