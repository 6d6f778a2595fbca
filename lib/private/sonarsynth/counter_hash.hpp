// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth::counter_hash {

/// A keyed counter-based hash in 32-bit words, written so that it vectorises (32-bit lanes:
/// xor, shift and 32 x 32 -> 32 multiply only); counter_hash-inl.hpp is the same function on
/// Highway vectors, lane for lane equal to this one (docs/physics.md §1.6 lists which draws use
/// it). Every word is a pure function of (stream, key, counter): no state, no order.
///
/// Mixer: "lowbias32" (Chris Wellons, "Prospecting for hash functions", 2018, public domain), a
/// bijection of the 32-bit integers with a measured avalanche bias of 0.17 %.
constexpr std::uint32_t mix32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x21f0aaadU;
  x ^= x >> 15;
  x *= 0x735a2d97U;
  x ^= x >> 15;
  return x;
}

/// The per-stream constants (a seed and a salt, e.g. a look, folded by splitmix64).
struct Stream {
  std::uint32_t s0 = 0, s1 = 0, s2 = 0;
  static constexpr Stream of(std::uint64_t seed) {
    const std::uint64_t a = splitmix64(seed), b = splitmix64(a);
    return {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(a >> 32),
            static_cast<std::uint32_t>(b)};
  }
};

/// The hash of a 64-bit key given as its two halves (distinct keys differing in one half never
/// collide: each step is a bijection of what it reads).
constexpr std::uint32_t key_word(const Stream& s, std::uint32_t key_lo, std::uint32_t key_hi) {
  return mix32(mix32(key_lo ^ s.s0) ^ key_hi ^ s.s1);
}
constexpr std::uint32_t key_word(const Stream& s, std::uint64_t key) {
  return key_word(s, static_cast<std::uint32_t>(key), static_cast<std::uint32_t>(key >> 32));
}

/// Word number `counter` of the key whose key_word is `h` (a Weyl sequence in the counter, one
/// mix per word).
constexpr std::uint32_t draw(const Stream& s, std::uint32_t h, std::uint32_t counter) {
  return mix32(h ^ (s.s2 + counter * 0x9e3779b9U));
}

/// A uniform float in (0, 1) from the high 24 bits of a word: the midpoint of its 2^-24 cell,
/// never 0 or 1 (safe for log of either it or 1 - it).
constexpr float uniform_open(std::uint32_t w) {
  return static_cast<float>(w >> 8) * 0x1p-24f + 0x1p-25f;
}

}  // namespace sonarsynth::counter_hash
