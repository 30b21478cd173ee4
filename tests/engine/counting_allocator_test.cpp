// The replacement of the global operator new shared by the engine tests (counting_allocator.h).
// A replacement must be defined exactly once per program, hence this one file; its test checks
// that the counter does count.
#include "tests/engine/counting_allocator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

static std::atomic<long> g_allocations{0};

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace ps::test {
long allocations() { return g_allocations.load(); }
}  // namespace ps::test

namespace ps {
namespace {

TEST(CountingAllocator, CountsEveryOperatorNew) {
  const long before = test::allocations();
  auto p = std::make_unique<int>(3);
  std::vector<double> v(10);
  EXPECT_EQ(test::allocations() - before, 2);
  EXPECT_EQ(*p + static_cast<int>(v.size()), 13);
}

}  // namespace
}  // namespace ps
