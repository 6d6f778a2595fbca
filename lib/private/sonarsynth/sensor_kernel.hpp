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
struct DetectorArgs {
  const std::uint64_t* keys = nullptr;        ///< frozen-speckle keys
  const std::uint64_t* noise_keys = nullptr;  ///< fresh-noise keys
  const double* base = nullptr;               ///< textured mean intensity before TVG
  const double* gain = nullptr;               ///< TVG x quantiser gain
  /// Frozen speckle power of every look, look-major (look j at field[j n .. (j + 1) n)), NaN
  /// where it is drawn from the speckle stream instead; nullptr: drawn everywhere.
  const double* field = nullptr;
  double* out = nullptr;  ///< detected output power
  std::size_t n = 0;
  int looks = 1;
  bool max_detector = true;    ///< max over looks (else the square of the mean envelope)
  double thermal_power = 0.0;  ///< N, before the gain; 0 = off
  double floor_power = 0.0;    ///< mean receiver-noise power, output domain; 0 = off
  std::uint64_t seed = 0;
};

/// Per sample i and look j (docs/physics.md §1.6): A = base gain E_s (E_s = field, or
/// -ln u of the speckle word; skipped where base is 0), the thermal noise of power M = N gain
/// added to the frozen field before detection as the complex-Gaussian power directly,
/// p = A + M E + 2 sqrt(A M E) cos(theta), E = -ln u, theta uniform; plus floor_power
/// (-ln u); the looks combined by max or by the square of the mean of sqrt p. Computed in
/// float32 on the dispatched target (simd::configure_from_environment applied first).
void detect(const DetectorArgs& a);

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
