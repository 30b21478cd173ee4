#pragma once
// PS_TARGET_CLONES("avx", "default"): build a hot kernel for several instruction sets and let the
// dynamic loader pick one (GCC function multiversioning, an ifunc). The selection runs in the
// loader before any sanitizer runtime is up, so an instrumented resolver crashes the binary at
// load (under ThreadSanitizer: SIGSEGV in the resolver of ps::project_volumes).
// Sanitizer builds define PROSTATESIM_NO_MULTIVERSION and get the baseline build only; every
// clone does the same operations in the same order, so results do not depend on the choice.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__ELF__) && !defined(PROSTATESIM_NO_MULTIVERSION)
#define PS_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#else
#define PS_TARGET_CLONES(...)
#endif

// GCC's per-function optimisation level, for kernels that need -O3's vectoriser in an -O2 build
#if defined(__GNUC__) && !defined(__clang__)
#define PS_OPTIMIZE_O3 __attribute__((optimize("O3")))
#else
#define PS_OPTIMIZE_O3
#endif
