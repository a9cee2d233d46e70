// bitstream.hpp - bounds-checked little-endian reading for the file format
// (docs/FORMAT.md; writer/byte_writer.hpp writes what it reads). Every read
// checks the remaining length and throws a corrupt-file error naming what
// was being read; nothing is ever read past the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace vqtex {

class ByteReader {
public:
    // `what` names the structure being read, for error messages.
    ByteReader(const uint8_t* data, std::size_t size, std::string what)
        : data_(data), size_(size), what_(std::move(what)) {}

    uint8_t u8(const char* field);
    uint16_t u16(const char* field);
    uint32_t u32(const char* field);
    uint64_t u64(const char* field);
    uint64_t varint(const char* field);
    // A varint that must lie in [lo, hi].
    uint64_t varint_in(const char* field, uint64_t lo, uint64_t hi);
    const uint8_t* bytes(std::size_t n, const char* field);
    std::size_t remaining() const { return size_ - pos_; }
    std::size_t position() const { return pos_; }
    // Throws unless everything was consumed.
    void expect_end() const;
    [[noreturn]] void corrupt(const std::string& detail) const;

private:
    void need(std::size_t n, const char* field) const;
    const uint8_t* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
    std::string what_;
};

}  // namespace vqtex
