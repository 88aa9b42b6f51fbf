#pragma once
// The generators' random numbers: SplitMix64, so that the same seed gives the same file on every
// machine and C++ library (std:: distributions are not portable).

#include <cstdint>

namespace orbis::gen {

struct SplitMix {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

}  // namespace orbis::gen
