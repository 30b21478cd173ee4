// Counting allocator shared by the engine tests: the replacement operator new of the
// engine_tests binary (tests/engine/counting_allocator_test.cpp, one definition per binary)
// bumps one counter on every allocation of any thread. A test reads it around the code that
// must not allocate (the physics step, every Tool hook):
//   const long before = test::allocation_count();  ...;  EXPECT_EQ(test::allocation_count() - before, 0);
#pragma once

namespace ps::test {

long allocation_count();

}  // namespace ps::test
