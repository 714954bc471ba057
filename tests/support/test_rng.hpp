// A small portable random generator for property tests: std::mt19937_64 with our own mapping
// (not std distributions), so the generated shapes are the same with every standard library.
#pragma once

#include <cstdint>
#include <random>

namespace carve::test {

struct Rng {
    std::mt19937_64 engine;
    explicit Rng(uint64_t seed) : engine(seed) {}
    double uniform(double lo, double hi) {
        return lo + (hi - lo) * double(engine() >> 11) * (1.0 / 9007199254740992.0);
    }
    int integer(int lo, int hi) { return lo + int(engine() % uint64_t(hi - lo + 1)); }
};

}  // namespace carve::test
