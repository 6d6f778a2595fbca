// SPDX-License-Identifier: MIT
#include "sonarsynth/noise.hpp"

#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth {
namespace {
// Stream numbers: disjoint ranges per purpose (keyed_gamma uses up to 1 + 3 per attempt).
constexpr std::uint64_t kStreamPaperUniform = 0;
constexpr std::uint64_t kStreamPaperRayleigh = 1;
constexpr std::uint64_t kStreamSpeckle = 2;  // 2, 3
constexpr std::uint64_t kStreamThermal = 4;  // 4, 5 (keyed by noise_keys)
constexpr std::uint64_t kStreamTexture = 1u << 20;
// Separates thermal-noise draws from speckle draws that happen to share a key value.
constexpr std::uint64_t kThermalSalt = 0x7468657266616c21ULL;

void check_size(const char* what, std::size_t n, std::size_t expected) {
  if (n != expected) {
    throw InputError(
        std::string("noise: ") + what + ".size() = " + std::to_string(n) +
        ". Violated constraint: size == intensity.size() = " + std::to_string(expected));
  }
}
}  // namespace

void PaperNoise::validate() const {
  if (!(uniform_half_width >= 0.0 && uniform_half_width <= 1.0)) {
    throw InputError("paper noise: uniform_half_width = " + std::to_string(uniform_half_width) +
                     ". Violated constraint: 0 <= uniform_half_width <= 1");
  }
  if (!(std::isfinite(rayleigh_sigma) && rayleigh_sigma >= 0.0)) {
    throw InputError("paper noise: rayleigh_sigma = " + std::to_string(rayleigh_sigma) +
                     ". Violated constraint: rayleigh_sigma >= 0");
  }
}

void SpeckleNoise::validate() const {
  if (!(std::isfinite(thermal_noise_power) && thermal_noise_power >= 0.0)) {
    throw InputError("speckle noise: thermal_noise_power = " + std::to_string(thermal_noise_power) +
                     ". Violated constraint: thermal_noise_power >= 0");
  }
}

void apply_paper_noise(const PaperNoise& noise, std::span<const std::uint64_t> keys,
                       std::span<double> intensity) {
  noise.validate();
  check_size("keys", keys.size(), intensity.size());
  const double a = noise.uniform_half_width;
  const double sigma = noise.rayleigh_sigma;
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    const double u =
        a * (2.0 * uniform_from_bits(keyed_hash(noise.seed, keys[i], kStreamPaperUniform)) - 1.0);
    double r = 0.0;
    if (sigma > 0.0) {
      // Rayleigh by inversion: r = sigma sqrt(-2 ln U), U in (0, 1].
      const double v =
          uniform_open0_from_bits(keyed_hash(noise.seed, keys[i], kStreamPaperRayleigh));
      r = sigma * std::sqrt(-2.0 * std::log(v));
    }
    intensity[i] = intensity[i] * (1.0 + u) + r;
  }
}

void apply_speckle_noise(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> texture_nu, std::span<double> intensity) {
  noise.validate();
  const std::size_t n = intensity.size();
  check_size("keys", keys.size(), n);
  check_size("noise_keys", noise_keys.size(), n);
  if (!texture_nu.empty()) check_size("texture_nu", texture_nu.size(), n);
  const double half_n = 0.5 * noise.thermal_noise_power;
  for (std::size_t i = 0; i < n; ++i) {
    double mean = intensity[i];
    if (!texture_nu.empty()) {
      const double nu = texture_nu[i];
      if (!(nu >= 0.0) || !std::isfinite(nu)) {
        throw InputError("speckle noise: texture_nu[" + std::to_string(i) +
                         "] = " + std::to_string(nu) + ". Violated constraint: texture_nu >= 0");
      }
      // Unit-mean Gamma(nu, 1/nu) texture (K-distribution, reference §1.6).
      if (nu > 0.0 && mean > 0.0) {
        mean *= keyed_gamma(nu, noise.seed, keys[i], kStreamTexture) / nu;
      }
    }
    double re = 0.0, im = 0.0;
    if (mean > 0.0) {
      const NormalPair s = keyed_normal_pair(noise.seed, keys[i], kStreamSpeckle);
      const double a = std::sqrt(0.5 * mean);
      re = a * s.n1;
      im = a * s.n2;
    }
    if (half_n > 0.0) {
      // Thermal noise added to the complex field before detection (Rician amplitude).
      const NormalPair t =
          keyed_normal_pair(noise.seed ^ kThermalSalt, noise_keys[i], kStreamThermal);
      const double b = std::sqrt(half_n);
      re += b * t.n1;
      im += b * t.n2;
    }
    intensity[i] = re * re + im * im;
  }
}

}  // namespace sonarsynth
