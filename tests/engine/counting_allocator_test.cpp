// The engine_tests binary's replacement operator new (see counting_allocator.h) and a check that
// it counts.
#include "tests/engine/counting_allocator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The array and nothrow forms too: libstdc++'s call the scalar ones, but a sanitizer runtime
// (ASan, TSan) brings its own that go straight to its allocator. Without these the no-allocation
// tests would not see arrays in the sanitizer builds, and memory from the runtime's nothrow new
// (std::stable_sort's temporary buffer) came back through the free() below: ASan's
// alloc-dealloc-mismatch in every test that builds a needle tool (found by .ci/sanitize).
void* operator new[](std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace ps::test {
long allocation_count() { return g_allocations.load(std::memory_order_relaxed); }
}  // namespace ps::test

namespace ps {
namespace {

TEST(CountingAllocator, CountsEveryNew) {
  const long before = test::allocation_count();
  auto a = std::make_unique<int>(1);
  auto b = std::make_unique<double[]>(8);
  int* c = new (std::nothrow) int(3);
  delete c;
  EXPECT_EQ(test::allocation_count() - before, 3);
}

}  // namespace
}  // namespace ps
