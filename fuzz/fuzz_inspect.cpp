// fuzz_inspect.cpp - libFuzzer target: any bytes as a .vqt file through
// vqtex_inspect, which runs every check the decoder runs (container,
// sections, zstd, codebooks) without synthesising. Inputs whose only fault
// is the checksum are inspected again with the checksum repaired.
#include "fuzz_support.hpp"

using namespace vqtex_fuzz;

namespace {

constexpr uint64_t kMemoryLimit = 32u << 20;

void check_info(const vqtex_file_info& info, size_t size) {
    if (info.file_bytes != size) violated("file_bytes differs from the input size");
    if (info.channels < 1 || info.channels > 4) violated("accepted channel count out of range");
    if (info.levels < 1 || info.levels > VQTEX_MAX_LEVELS) violated("accepted level count out of range");
    if (info.section_count > VQTEX_MAX_SECTIONS) violated("section_count above VQTEX_MAX_SECTIONS");
    uint64_t stored = 0;
    for (uint32_t i = 0; i < info.section_count; ++i) {
        if (info.sections[i].tag[4] != '\0') violated("section tag not NUL-terminated");
        stored += info.sections[i].stored_bytes;
    }
    if (stored > size) violated("sections claim more bytes than the file has");
    for (uint32_t l = 0; l < info.levels; ++l)
        if (info.codewords[l] == 0) violated("an accepted level without codewords");
}

vqtex_status inspect(const uint8_t* data, size_t size) {
    vqtex_file_info info;
    vqtex_error err;
    const vqtex_status st = vqtex_inspect(data, size, kMemoryLimit, &info, &err);
    if (st == VQTEX_OK)
        check_info(info, size);
    else
        check_failure(st, err);
    return st;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (inspect(data, size) == VQTEX_ERROR_CHECKSUM) {
        const std::vector<uint8_t> repaired = with_valid_checksum(data, size);
        inspect(repaired.data(), repaired.size());
    }
    return 0;
}
