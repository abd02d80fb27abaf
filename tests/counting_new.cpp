// The counting allocator (counting_new.hpp). A header before each block holds its size; the
// header is as wide as the block's alignment.
#include "counting_new.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<size_t> g_live{0}, g_peak{0};

size_t header_of(size_t align) {
  return align < sizeof(size_t) * 2 ? sizeof(size_t) * 2 : align;
}

void* counted_new(size_t bytes, size_t align) {
  const size_t header = header_of(align);
  void* raw = std::aligned_alloc(header, ((header + bytes + header - 1) / header) * header);
  if (!raw) throw std::bad_alloc();
  *static_cast<size_t*>(raw) = bytes;
  const size_t live = g_live.fetch_add(bytes) + bytes;
  size_t peak = g_peak.load();
  while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {
  }
  return static_cast<char*>(raw) + header;
}

void counted_delete(void* p, size_t align) noexcept {
  if (!p) return;
  void* raw = static_cast<char*>(p) - header_of(align);
  g_live.fetch_sub(*static_cast<size_t*>(raw));
  std::free(raw);
}

}  // namespace

namespace plastivox::test {

PeakScope::PeakScope() : base_(g_live.load()) {
  g_peak.store(base_);
}

size_t PeakScope::peak() const {
  return g_peak.load() - base_;
}

}  // namespace plastivox::test

void* operator new(size_t n) {
  return counted_new(n, 0);
}
void* operator new[](size_t n) {
  return counted_new(n, 0);
}
void* operator new(size_t n, std::align_val_t a) {
  return counted_new(n, static_cast<size_t>(a));
}
void* operator new[](size_t n, std::align_val_t a) {
  return counted_new(n, static_cast<size_t>(a));
}
void operator delete(void* p) noexcept {
  counted_delete(p, 0);
}
void operator delete[](void* p) noexcept {
  counted_delete(p, 0);
}
void operator delete(void* p, size_t) noexcept {
  counted_delete(p, 0);
}
void operator delete[](void* p, size_t) noexcept {
  counted_delete(p, 0);
}
void operator delete(void* p, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete[](void* p, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete(void* p, size_t, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete[](void* p, size_t, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
