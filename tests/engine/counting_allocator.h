// Counting allocator of the engine test binary: the global operator new of engine_tests is
// replaced once (counting_allocator_test.cpp) so that every heap allocation, by the engine or by
// a library it calls (Eigen, FCL, the standard library), bumps one counter. Tests of the
// no-allocation rule read it around the ticks they check:
//   const long before = test::allocations();  ...ticks...  EXPECT_EQ(test::allocations() - before, 0);
#pragma once

namespace ps::test {

long allocations();  // operator new calls so far in this process

}  // namespace ps::test
