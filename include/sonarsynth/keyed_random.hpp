// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <cstdint>

namespace sonarsynth {

/// Counter-based (keyed) random numbers: every draw is a pure function of (seed, key, stream),
/// so results do not depend on the order of evaluation or on the number of threads, and are
/// identical across standard libraries (no std:: distributions are used).
///
/// Mixer: splitmix64 finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014; constants from Vigna's public-domain splitmix64.c).
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Hash of an ordered tuple of 64-bit words (chained splitmix64).
constexpr std::uint64_t hash_combine(std::uint64_t h, std::uint64_t v) {
  return splitmix64(h ^ splitmix64(v));
}
constexpr std::uint64_t keyed_hash(std::uint64_t seed, std::uint64_t key, std::uint64_t stream) {
  return hash_combine(hash_combine(splitmix64(seed), key), stream);
}

/// Uniform double in [0, 1) from the top 53 bits of a 64-bit word.
constexpr double uniform_from_bits(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}
/// Uniform double in (0, 1]: safe for log().
constexpr double uniform_open0_from_bits(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 1.0) * 0x1.0p-53;
}

/// A pair of independent standard normal numbers by the Box–Muller transform
/// (Box & Muller, Ann. Math. Statist. 29(2):610-611, 1958) from the keyed uniforms of `stream`
/// and `stream + 1`.
struct NormalPair {
  double n1;
  double n2;
};
inline NormalPair keyed_normal_pair(std::uint64_t seed, std::uint64_t key, std::uint64_t stream) {
  const double u1 = uniform_open0_from_bits(keyed_hash(seed, key, stream));
  const double u2 = uniform_from_bits(keyed_hash(seed, key, stream + 1));
  const double rad = std::sqrt(-2.0 * std::log(u1));
  const double ang = 6.283185307179586476925 * u2;
  return {rad * std::cos(ang), rad * std::sin(ang)};
}

/// Gamma(shape, scale = 1) by Marsaglia & Tsang, "A simple method for generating gamma
/// variables", ACM TOMS 26(3):363-372, 2000; for shape < 1 the boost Gamma(shape + 1) * U^(1/shape)
/// from the same paper. Keyed: uses streams stream, stream + 1, ... (at most 4 per attempt).
/// shape must be > 0.
double keyed_gamma(double shape, std::uint64_t seed, std::uint64_t key, std::uint64_t stream);

}  // namespace sonarsynth
