// alloc_counter.hpp - measures the peak of live operator-new bytes during a
// call, so tests can assert that a hostile file never makes the decoder
// allocate beyond its memory limit. Linked only into the tests that use it
// (it replaces the global operator new and delete of that executable).
#pragma once

#include <cstddef>

namespace vqtex_test {

// Live bytes allocated with operator new right now.
std::size_t live_bytes();

// Runs fn and returns the highest number of live bytes above the starting
// level at any moment during it (the calling thread's and any other's).
template <typename Fn>
std::size_t peak_bytes_during(Fn&& fn);

namespace detail {
void reset_peak();
std::size_t peak();
}  // namespace detail

template <typename Fn>
std::size_t peak_bytes_during(Fn&& fn) {
    const std::size_t start = live_bytes();
    detail::reset_peak();
    fn();
    const std::size_t top = detail::peak();
    return top > start ? top - start : 0;
}

}  // namespace vqtex_test
