// SPDX-License-Identifier: MIT
#include "sonarsynth/noise.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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
  const double shift = noise.uniform_from_zero ? a : 0.0;  // U(-a, a) + a = U(0, 2 a)
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    const double u =
        shift +
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

namespace {

// The reference sampler: the complex field by Box–Muller, the texture by Marsaglia–Tsang.
void speckle_exact(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                   std::span<const std::uint64_t> noise_keys, std::span<const double> texture_nu,
                   std::span<const double> field, std::span<double> intensity) {
  const double half_n = 0.5 * noise.thermal_noise_power;
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    double mean = intensity[i];
    if (!texture_nu.empty()) {
      const double nu = texture_nu[i];
      // Unit-mean Gamma(nu, 1/nu) texture (K-distribution, docs/physics.md §1.6).
      if (nu > 0.0 && mean > 0.0) {
        mean *= keyed_gamma(nu, noise.seed, keys[i], kStreamTexture) / nu;
      }
    }
    double re = 0.0, im = 0.0;
    if (mean > 0.0 && !field.empty() && !std::isnan(field[i])) {
      re = std::sqrt(mean * field[i]);  // the given field's power; its phase is immaterial
    } else if (mean > 0.0) {
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

// Texture samplers of the distinct nu values met in one call (few materials): a linear scan of
// a short list avoids the process-wide cache's lock per sample.
class TextureTables {
 public:
  const UnitGammaTable* find(double nu) {
    for (const Entry& e : entries_) {
      if (e.nu == nu) return e.table;
    }
    const UnitGammaTable* t = nu <= UnitGammaTable::kMaxShape ? &UnitGammaTable::get(nu) : nullptr;
    entries_.push_back({nu, t});
    return t;
  }

 private:
  struct Entry {
    double nu;
    const UnitGammaTable* table;  // nullptr: beyond the tables, keyed_gamma
  };
  std::vector<Entry> entries_;
};

// The tables sampler (see SpeckleSampler::tables for the method). Two keyed 64-bit words per
// sample, each split into two 32-bit uniforms (the halves of one mixed output are each uniform
// and jointly independent to the mixer's quality):
//  - frozen part: hk = splitmix_stream(seed, key), E_s from its high half, T from its low half;
//    runs of samples sharing (key, nu) reuse the product T E_s;
//  - thermal part: hn = wyrand_stream(seed', noise_key) (one word per sample and look: the
//    cheaper mixer), the noise field's two standard normals g1, g2
//    from the 16-bit quarters of its high half (NormalTable); the low 32 bits are the
//    detector's receiver noise.
// UnitGammaTable takes the top 12 bits of a half as the bin and the next 20 as the position in
// it, completed by high32_midpoint so the position is the centre of one of 2^20 equal cells
// (unbiased). Resolution 2^-32 in probability for E_s and T (tails cut at probability 2^-33,
// Exp(1) at ~22.9), 2^-16 for g1, g2 (|g| <= 4.3, where the thermal noise is a small additive
// term), far below what the KS / moment tests or an image resolve.
void speckle_tables(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                    std::span<const std::uint64_t> noise_keys, std::span<const double> texture_nu,
                    std::span<const double> field, std::span<double> intensity) {
  const UnitGammaTable& exp1 = UnitGammaTable::get(1.0);
  const NormalTable& normal = NormalTable::get();
  const double n_power = noise.thermal_noise_power;
  const double half_n = 0.5 * n_power, sqrt_half_n = std::sqrt(half_n);
  const std::uint64_t seed_s = speckle_seed(noise.seed);
  const std::uint64_t seed_n = thermal_seed(noise.seed);
  const bool textured = !texture_nu.empty();
  TextureTables tables;
  double last_nu = 0.0;
  const UnitGammaTable* last_table = nullptr;
  // Cache of the frozen multiplier T E_s of the last (key, nu).
  bool have_frozen = false;
  std::uint64_t frozen_key = 0;
  double frozen_nu = 0.0, frozen = 0.0;
  bool frozen_given = false;
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    double a = intensity[i];  // A = I T E_s
    if (a > 0.0) {
      const double nu = textured ? texture_nu[i] : 0.0;
      const bool given = !field.empty() && !std::isnan(field[i]);
      if (!have_frozen || keys[i] != frozen_key || nu != frozen_nu || given != frozen_given) {
        const std::uint64_t hk = splitmix_stream(seed_s, keys[i]);
        double m = given ? 1.0 : exp1(high32_midpoint(hk));
        if (nu > 0.0) {
          if (nu != last_nu) {
            last_nu = nu;
            last_table = tables.find(nu);
          }
          m *= last_table != nullptr ? (*last_table)(high32_midpoint(hk << 32))
                                     : keyed_gamma(nu, noise.seed, keys[i], kStreamTexture) / nu;
        }
        have_frozen = true;
        frozen_key = keys[i];
        frozen_nu = nu;
        frozen_given = given;
        frozen = m;
      }
      a *= frozen;
      if (given) a *= field[i];
    }
    if (n_power > 0.0)
      a = add_thermal_noise(a, half_n, sqrt_half_n, wyrand_stream(seed_n, noise_keys[i]), normal);
    intensity[i] = a;
  }
}

}  // namespace

void check_speckle_inputs(const SpeckleNoise& noise, std::size_t n,
                          std::span<const std::uint64_t> keys,
                          std::span<const std::uint64_t> noise_keys,
                          std::span<const double> texture_nu, std::span<const double> field) {
  noise.validate();
  check_size("keys", keys.size(), n);
  check_size("noise_keys", noise_keys.size(), n);
  if (!texture_nu.empty()) check_size("texture_nu", texture_nu.size(), n);
  if (!field.empty()) check_size("field", field.size(), n);
  for (std::size_t i = 0; i < texture_nu.size(); ++i) {
    const double nu = texture_nu[i];
    if (!(nu >= 0.0) || !std::isfinite(nu)) {
      throw InputError("speckle noise: texture_nu[" + std::to_string(i) +
                       "] = " + std::to_string(nu) + ". Violated constraint: texture_nu >= 0");
    }
  }
}

void apply_speckle_noise(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> texture_nu, std::span<double> intensity) {
  apply_speckle_noise(noise, keys, noise_keys, texture_nu, {}, intensity);
}

void apply_speckle_noise(const SpeckleNoise& noise, std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> texture_nu, std::span<const double> field,
                         std::span<double> intensity) {
  check_speckle_inputs(noise, intensity.size(), keys, noise_keys, texture_nu, field);
  if (noise.sampler == SpeckleSampler::exact) {
    speckle_exact(noise, keys, noise_keys, texture_nu, field, intensity);
  } else {
    speckle_tables(noise, keys, noise_keys, texture_nu, field, intensity);
  }
}

}  // namespace sonarsynth
