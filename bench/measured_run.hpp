// How vqtex-bench measures each vqtex encode, decode and synthesis: in a
// forked child of its own, so that its peak memory is its own (the child's
// high-water mark minus what it inherited) and its wall time is not mixed
// with the scoring. The child hands its results back through files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace vqtex_tools {

// Runs `work` in a forked child; true when the child returned true. Sets
// the memory the child added (KiB) and the wall time.
bool measured(const std::function<bool()>& work, long& peak_kib, double& seconds);

// A whole file (empty if it does not read), and a buffer written to a file.
std::vector<uint8_t> read_all(const std::string& path);
bool write_all(const std::string& path, const uint8_t* data, std::size_t n);

}  // namespace vqtex_tools
