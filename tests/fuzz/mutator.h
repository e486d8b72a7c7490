// Deterministic input mutations for iblx_fuzz (tests/fuzz/fuzz_runner.cpp): truncations, bit flips, bytes
// and length fields set to extremes, numbers in text set to extremes, and random splices with other corpus
// inputs. Everything derives from one 64-bit seed through SplitMix64, so a run is replayed exactly by its
// seed and iteration on any machine and compiler (no std:: distributions, whose output is not portable).
#pragma once

#include "tests/fuzz/fuzz_target.h"

#include <cstddef>
#include <cstdint>

namespace iblx::fuzz {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform enough in [0, n) for n far below 2^64 (n > 0).
  std::size_t below(std::size_t n) { return std::size_t(next() % n); }
  bool chance(unsigned oneIn) { return below(oneIn) == 0; }

 private:
  std::uint64_t state_;
};

// Applies one to four mutations to `input`, drawing splice material from `corpus`; the result is at most
// maxBytes long.
Bytes mutate(const Bytes& input, std::span<const Bytes> corpus, SplitMix64& rng, std::size_t maxBytes);

}  // namespace iblx::fuzz
