// byte_writer.cpp - little-endian integers and LEB128 varints
// (docs/FORMAT.md §1), as common/bitstream.cpp reads them.
#include "writer/byte_writer.hpp"

namespace vqtex {

void ByteWriter::u16(uint16_t v) {
    u8(uint8_t(v));
    u8(uint8_t(v >> 8));
}
void ByteWriter::u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(uint8_t(v >> (8 * i)));
}
void ByteWriter::u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(uint8_t(v >> (8 * i)));
}
void ByteWriter::varint(uint64_t v) {
    while (v >= 0x80) {
        u8(uint8_t(v | 0x80));
        v >>= 7;
    }
    u8(uint8_t(v));
}

}  // namespace vqtex
