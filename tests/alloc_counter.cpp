// alloc_counter.cpp - replacement global operator new/delete that keep a
// running total and a peak of live bytes (see alloc_counter.hpp). Each block
// carries its size in a 16-byte header, which keeps the alignment
// operator new promises.
#include "alloc_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<std::size_t> g_live{0};
std::atomic<std::size_t> g_peak{0};
constexpr std::size_t kHeader = 16;
static_assert(kHeader >= alignof(std::max_align_t));

void* counted_alloc(std::size_t n) {
    void* raw = std::malloc(n + kHeader);
    if (!raw) return nullptr;
    *static_cast<std::size_t*>(raw) = n;
    const std::size_t now = g_live.fetch_add(n, std::memory_order_relaxed) + n;
    std::size_t peak = g_peak.load(std::memory_order_relaxed);
    while (now > peak && !g_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
    return static_cast<char*>(raw) + kHeader;
}

void counted_free(void* p) noexcept {
    if (!p) return;
    void* raw = static_cast<char*>(p) - kHeader;
    g_live.fetch_sub(*static_cast<std::size_t*>(raw), std::memory_order_relaxed);
    std::free(raw);
}

}  // namespace

namespace vqtex_test {
std::size_t live_bytes() { return g_live.load(); }
namespace detail {
void reset_peak() { g_peak.store(g_live.load()); }
std::size_t peak() { return g_peak.load(); }
}  // namespace detail
}  // namespace vqtex_test

void* operator new(std::size_t n) {
    if (void* p = counted_alloc(n)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
    if (void* p = counted_alloc(n)) return p;
    throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
