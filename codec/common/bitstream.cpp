// bitstream.cpp - the bounds-checked little-endian reader.
#include "common/bitstream.hpp"

#include "common/error.hpp"

namespace vqtex {

void ByteReader::corrupt(const std::string& detail) const {
    fail(VQTEX_ERROR_CORRUPT, what_ + " at byte " + std::to_string(pos_) + ": " + detail);
}

void ByteReader::need(std::size_t n, const char* field) const {
    if (n > size_ - pos_)
        corrupt(std::string("ends before ") + field + " (" + std::to_string(n) + " bytes needed, " +
                std::to_string(size_ - pos_) + " left)");
}

uint8_t ByteReader::u8(const char* field) {
    need(1, field);
    return data_[pos_++];
}
uint16_t ByteReader::u16(const char* field) {
    need(2, field);
    const uint16_t v = uint16_t(data_[pos_] | (data_[pos_ + 1] << 8));
    pos_ += 2;
    return v;
}
uint32_t ByteReader::u32(const char* field) {
    need(4, field);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(data_[pos_ + std::size_t(i)]) << (8 * i);
    pos_ += 4;
    return v;
}
uint64_t ByteReader::u64(const char* field) {
    need(8, field);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(data_[pos_ + std::size_t(i)]) << (8 * i);
    pos_ += 8;
    return v;
}
uint64_t ByteReader::varint(const char* field) {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
        const uint8_t b = u8(field);
        // Only the minimal encoding is valid: no bits beyond 64, no
        // trailing zero groups.
        if (shift == 63 && b > 1) corrupt(std::string(field) + " overflows 64 bits");
        if (shift > 0 && b == 0) corrupt(std::string(field) + " is not minimally encoded");
        v |= uint64_t(b & 0x7F) << shift;
        if (!(b & 0x80)) return v;
    }
    corrupt(std::string(field) + " is not a valid varint (too long)");
}
uint64_t ByteReader::varint_in(const char* field, uint64_t lo, uint64_t hi) {
    const uint64_t v = varint(field);
    if (v < lo || v > hi)
        corrupt(std::string(field) + " is " + std::to_string(v) + ", outside " + std::to_string(lo) +
                ".." + std::to_string(hi));
    return v;
}
const uint8_t* ByteReader::bytes(std::size_t n, const char* field) {
    need(n, field);
    const uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
}
void ByteReader::expect_end() const {
    if (pos_ != size_) corrupt(std::to_string(size_ - pos_) + " unexpected bytes after the data");
}

}  // namespace vqtex
