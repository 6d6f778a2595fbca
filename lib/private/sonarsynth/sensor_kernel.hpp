// SPDX-License-Identifier: MIT
// The vector kernel of the detector stage (lib/sensor_kernel.cpp, docs/physics.md §1.6):
// frozen speckle, thermal noise, receiver noise floor, TVG gain and the detector's looks in one
// fused pass over blocks of float32 samples, dispatched at run time (AVX-512, AVX2, scalar).
// Internal.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sonarsynth/counter_hash.hpp"

namespace sonarsynth::sensor_kernel {

/// The counter-hash stream of the frozen speckle (keyed by the seabed cell) and of the fresh
/// noise (keyed by ping, side and sample) of a run seed: distinct streams, so that a sample
/// whose two keys are equal (water column, shadow) still draws them independently.
counter_hash::Stream speckle_stream(std::uint64_t seed);
counter_hash::Stream noise_stream(std::uint64_t seed);

/// Look j's words: the speckle word is draw(speckle, key_word(speckle, key), j); the noise
/// words draw(noise, key_word(noise, noise_key), 3 j + c), c = 0 the thermal power, 1 its phase,
/// 2 the receiver noise floor.
constexpr std::uint32_t kNoiseWordsPerLook = 3;

/// What detect() reads and writes; n samples each.
/// What both detectors (detect, detect_filtered) take.
struct DetectorCommon {
  const std::uint64_t* keys = nullptr;        ///< frozen-speckle keys
  const std::uint64_t* noise_keys = nullptr;  ///< fresh-noise keys
  const double* base = nullptr;               ///< textured mean intensity before TVG
  const double* gain = nullptr;               ///< TVG x quantiser gain
  double* out = nullptr;                      ///< detected output power
  std::size_t n = 0;
  int looks = 1;
  bool max_detector = true;    ///< max over looks (else the square of the mean envelope)
  double thermal_power = 0.0;  ///< N, before the gain; 0 = off
  double floor_power = 0.0;    ///< mean receiver-noise power, output domain; 0 = off
  std::uint64_t seed = 0;
};

struct DetectorArgs : DetectorCommon {
  /// Frozen speckle power of every look, look-major (look j at field[j n .. (j + 1) n)), NaN
  /// where it is drawn from the speckle stream instead; nullptr: drawn everywhere.
  const double* field = nullptr;
};

/// Per sample i and look j (docs/physics.md §1.6): A = base gain E_s (E_s = field, or
/// -ln u of the speckle word; skipped where base is 0), the thermal noise of power M = N gain
/// added to the frozen field before detection as the complex-Gaussian power directly,
/// p = A + M E + 2 sqrt(A M E) cos(theta), E = -ln u, theta uniform; plus floor_power
/// (-ln u); the looks combined by max or by the square of the mean of sqrt p. Computed in
/// float32 on the dispatched target (simd::configure_from_environment applied first).
void detect(const DetectorArgs& a);

/// The texture word of a key: draw(speckle, key_word(speckle, key), kTextureCounter) (beyond
/// every look's counter, so independent of the looks' speckle words). The filtered detector's
/// speckle phase of look j: draw(speckle, key_word(speckle, key), kPhaseCounter + j), its power
/// the look's speckle word.
constexpr std::uint32_t kTextureCounter = 0x7e470000U;
constexpr std::uint32_t kPhaseCounter = 0x9a5e0000U;

/// The seabed texture (docs/physics.md §1.6): base[i] = mean[i] T_i where mean[i] > 0 and
/// nu[i] > 0, else mean[i]; T unit-mean Gamma(nu) from the texture word w of keys[i], as
/// UnitGammaTable(nu) of the 64 bits high32_midpoint(w << 32), its bins' quadratic evaluated in
/// float32 (UnitGammaTable::bins_float; < 1e-6 relative from the double rule) except in the two
/// exactly inverted tail bins; beyond UnitGammaTable::kMaxShape, keyed_gamma (scalar).
/// nu == nullptr: no texture.
struct TextureArgs {
  const std::uint64_t* keys = nullptr;
  const double* nu = nullptr;
  const double* mean = nullptr;
  double* base = nullptr;
  std::size_t n = 0;
  std::uint64_t seed = 0;
};
void texture(const TextureArgs& a);

/// The range-filtered detector (docs/physics.md §1.6): per look j the complex echo of every
/// sample, z = sqrt(base) g (g the lattice field (field_re, field_im) sqrt(field_norm) where that
/// is not NaN, else sqrt(E) e^(i phi) from the speckle words, zero where base is not > 0) plus the
/// thermal noise sqrt(N E') e^(i psi) (noise words 3 j, 3 j + 1), filtered by the taps
/// (y_i = sum_k taps[k] z_(i + k - K), K = taps_n / 2, taps outside the record dropped and the
/// rest renormalised to unit power gain), detected as |y|^2 gain plus the floor (word 3 j + 2);
/// the looks combined as detect() does. Float32 in blocks with a halo of K samples.
struct FilteredArgs : DetectorCommon {
  /// The lattice's look sums (look j at field_re + j field_stride) and their norm per sample
  /// (NaN where the lattice does not apply); nullptr: drawn everywhere.
  const float* field_re = nullptr;
  const float* field_im = nullptr;
  const double* field_norm = nullptr;
  std::size_t field_stride = 0;
  const double* taps = nullptr;  ///< 2 K + 1 taps, K <= kMaxHalfTaps
  std::size_t taps_n = 0;
};
constexpr std::size_t kMaxHalfTaps = 64;
void detect_filtered(const FilteredArgs& a);

/// The quantiser of samples first .. n - 1 of `power` (docs/physics.md §1.10): v = power
/// (times gain when not null), its square root for amplitude output; not finite -> 0 (counted
/// invalid), >= max_value -> max_value (counted saturated), < 0 -> 0; rounded half away from
/// zero when `round`. Vectorised in double: the same bits on every target.
struct QuantiseArgs {
  const double* power = nullptr;
  const double* gain = nullptr;
  std::size_t first = 0, n = 0;
  bool amplitude = true;
  bool round = true;
  double max_value = 0.0;
};
void quantise(const QuantiseArgs& q, float* out, std::uint32_t& saturated, std::uint32_t& invalid);

}  // namespace sonarsynth::sensor_kernel
