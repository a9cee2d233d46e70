// byte_writer.hpp - little-endian byte writing for the file format
// (docs/FORMAT.md), the writers' side of common/bitstream.hpp's
// ByteReader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace vqtex {

class ByteWriter {
public:
    void u8(uint8_t v) { bytes_.push_back(v); }
    void u16(uint16_t v);
    void u32(uint32_t v);
    void u64(uint64_t v);
    void varint(uint64_t v);  // LEB128, 7 bits per byte
    void bytes(const uint8_t* data, std::size_t n) {
        if (n == 0) return;
        const std::size_t at = bytes_.size();
        bytes_.resize(at + n);
        std::memcpy(bytes_.data() + at, data, n);
    }
    void bytes(const std::vector<uint8_t>& v) { bytes(v.data(), v.size()); }
    std::vector<uint8_t>& data() { return bytes_; }
    std::size_t size() const { return bytes_.size(); }

private:
    std::vector<uint8_t> bytes_;
};

}  // namespace vqtex
