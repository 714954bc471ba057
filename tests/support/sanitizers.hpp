// What the tests do differently in the sanitizer build (scripts/sanitize.sh: clang's
// AddressSanitizer and UndefinedBehaviorSanitizer at -O1), where carve runs five to ten times
// slower and reserves terabytes of address space.
#pragma once

#include <vector>

// The sanitizer tree defines CARVE_TEST_SANITIZED for the tests, whose own code it does not
// instrument (tests/CMakeLists.txt); GCC and clang also say when a file is compiled with
// AddressSanitizer, through __SANITIZE_ADDRESS__ and __has_feature.
#if defined(CARVE_TEST_SANITIZED) || defined(__SANITIZE_ADDRESS__)
#define CARVE_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CARVE_TEST_ASAN 1
#endif
#endif

// Nothing runs under `ulimit -v` with AddressSanitizer's shadow memory: the tests of memory
// limits run in the normal build.
#if defined(CARVE_TEST_ASAN)
#define SKIP_UNDER_ULIMIT_V() \
    GTEST_SKIP() << "ulimit -v cannot run under AddressSanitizer (shadow memory)"
#else
#define SKIP_UNDER_ULIMIT_V() (void)0
#endif

namespace carve::test {

#if defined(CARVE_TEST_ASAN)
inline constexpr bool kUnderSanitizers = true;
#else
inline constexpr bool kUnderSanitizers = false;
#endif

// A test that repeats one check over several models or settings checks the first of them alone
// in the sanitizer build: what the sanitizers look for (memory errors, undefined behaviour) the
// first run reaches through the same code, and the Release suite runs them all. It keeps CI's
// sanitizer phase within its share of the 15 minutes (bench/results/ci_time.md).
template <class T>
std::vector<T> first_under_sanitizers(std::vector<T> all) {
    if (kUnderSanitizers && all.size() > 1) all.resize(1);
    return all;
}

}  // namespace carve::test

// A test whose every run of carve repeats what other tests run under the sanitizers, and checks
// what carve writes rather than how it gets there, runs in the Release suite alone: `why` names
// where its code runs under the sanitizers.
#define SKIP_UNDER_SANITIZERS(why)        \
    if (!::carve::test::kUnderSanitizers) \
        ;                                 \
    else                                  \
        GTEST_SKIP() << "left to the Release suite (the sanitizers run its code in " << why << ")"
