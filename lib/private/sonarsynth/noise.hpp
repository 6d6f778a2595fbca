// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <span>

#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth {

/// The founding paper's noise, eq. (2) of Gwon et al. (URAI 2017), kept for parity:
///   I' = I (1 + u) + r,  r ~ Rayleigh(sigma),
///   u ~ U(-a, a) (zero mean), or u ~ U(0, 2 a) with uniform_from_zero (docs/physics.md §1.6).
/// Either way Var[u] = a^2 / 3: the paper's "U(0, gamma), variance gamma" is uniform_from_zero
/// with a = sqrt(3 gamma) (support [0, sqrt(12 gamma)], E[u] = sqrt(3 gamma)).
/// Moments: E[I'] = I (1 + E[u]) + sigma sqrt(pi/2), multiplicative contrast
/// std(1 + u) / E[1 + u] = (a / sqrt(3)) / (1 + E[u]).
struct PaperNoise {
  double uniform_half_width = 0.1;  ///< a, dimensionless, [0, 1]
  double rayleigh_sigma = 0.0;      ///< sigma of the additive Rayleigh term, intensity units, >= 0
  std::uint64_t seed = 0;
  bool uniform_from_zero = false;  ///< u ~ U(0, 2 a) instead of U(-a, a)

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// How apply_speckle_noise draws its variates (same distribution either way).
enum class SpeckleSampler : std::uint8_t {
  /// Default, fast. The detected sum of the frozen speckle field s (|s|^2 = A) and the fresh
  /// noise field n (|n|^2 = B), both circular complex Gaussian and independent: with
  /// A = I T E_s, E_s ~ Exp(1), the phase of s uniform and independent of n, so
  ///   I' = |s + n|^2 = (sqrt(A) + sqrt(N / 2) g1)^2 + (N / 2) g2^2
  /// exactly in distribution, also jointly over pings (s frozen, n fresh), g1 and g2 standard
  /// normals. E_s and T come from UnitGammaTable (tabulated inverse CDF, error bounded in the
  /// tests), g1 and g2 from NormalTable; no Box–Muller, no rejection. n is skipped when N = 0.
  tables,
  /// Reference: Box–Muller pairs (keyed_normal_pair) and Marsaglia–Tsang Gamma (keyed_gamma)
  /// per sample, exactly as the formula below.
  exact,
};

/// Physical noise (docs/physics.md §1.6): per sample the complex circular Gaussian field
///   z = sqrt(I T / 2) (n1 + i n2) + sqrt(N / 2) (n3 + i n4),  output I' = |z|^2,
/// with T ~ Gamma(nu, 1/nu) (unit-mean texture: K-distributed intensity, SI = 1 + 2/nu) when
/// the sample's nu > 0, T = 1 otherwise (exponential intensity, SI = 1), and thermal noise of
/// mean power N added BEFORE detection (Rician amplitude). E[I'] = I + N.
struct SpeckleNoise {
  double thermal_noise_power = 0.0;  ///< N, mean noise intensity, same units as I, >= 0
  std::uint64_t seed = 0;
  SpeckleSampler sampler = SpeckleSampler::tables;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Seeds of the tables sampler's keyed words: the frozen part (E_s and T) is
/// splitmix_stream(seed_s, key), the thermal part wyrand_stream(seed_n, noise_key).
inline std::uint64_t speckle_seed(std::uint64_t seed) {
  return splitmix64(seed);
}
inline std::uint64_t thermal_seed(std::uint64_t seed) {
  constexpr std::uint64_t kThermalSalt = 0x7468657266616c21ULL;
  return splitmix64(seed ^ kThermalSalt);
}

/// The thermal step of the tables sampler: the frozen field s (power A = a) has a uniform phase
/// independent of the circular noise field n (power N = n_power), so after rotating both by it
///   |s + n|^2 = (sqrt(A) + sqrt(N / 2) g1)^2 + (N / 2) g2^2
/// exactly in distribution, g1 and g2 standard normals (NormalTable) from the low and high 16
/// bits of the high half of the keyed word `hn`; its low 32 bits are left for the caller (the
/// receiver noise of detect_speckle). `half_n` is N / 2 and `sqrt_half_n` its square root.
inline double add_thermal_noise(double a, double half_n, double sqrt_half_n, std::uint64_t hn,
                                const NormalTable& normal) {
  const auto hi = static_cast<std::uint32_t>(hn >> 32);
  const double g1 = normal(hi), g2 = normal(hi >> 16);
  const double re = std::sqrt(a) + sqrt_half_n * g1;
  return re * re + half_n * (g2 * g2);
}

/// The input checks of apply_speckle_noise for `n` samples (InputError naming the violated
/// constraint); `field` may be empty.
void check_speckle_inputs(const SpeckleNoise& noise, std::size_t n,
                          std::span<const std::uint64_t> keys,
                          std::span<const std::uint64_t> noise_keys,
                          std::span<const double> texture_nu, std::span<const double> field);

/// Random numbers are keyed, not sequential: sample i draws from hash(seed, keys[i], stream),
/// so output is bit-identical whatever the thread count or processing order. Callers give a
/// sample the key of its dominant seabed contributor's quantised ground position (speckle
/// "frozen per seabed location": overlapping pings see the same speckle) and water-column /
/// shadow samples a (ping, sample) key. The thermal-noise term uses hash(keys[i], noise_keys[i])
/// streams distinct from the speckle streams; pass noise_keys as the (ping, sample) keys so that
/// thermal noise is independent between pings.

/// Applies PaperNoise in place. keys.size() must equal intensity.size() (else InputError).
void apply_paper_noise(const PaperNoise& noise, std::span<const std::uint64_t> keys,
                       std::span<double> intensity);

/// Applies SpeckleNoise in place. keys (scatterer keys) and noise_keys (thermal keys) must have
/// intensity.size() entries; texture_nu has intensity.size() entries (0 = no texture) or is
/// empty (no texture anywhere). Throws InputError on size mismatch or nu < 0.
void apply_speckle_noise(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> texture_nu, std::span<double> intensity);
/// The same with the frozen speckle power given: `field[i]` (unit mean, >= 0) replaces E_s, so a
/// caller can supply a speckle field correlated between pings (keys[i] then keys the texture
/// only). An empty field, or a NaN entry, draws E_s as above.
void apply_speckle_noise(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> texture_nu, std::span<const double> field,
                         std::span<double> intensity);

}  // namespace sonarsynth
