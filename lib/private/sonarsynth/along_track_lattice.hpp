// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>

namespace sonarsynth {

/// The per-sample, look-independent part of the along-track speckle lattice
/// (along_track_speckle_looks, lib/sensor_effects.cpp), in arrays of `samples` entries: the four
/// float weights, the normalisation 1 / (2 sum w^2) (NaN where the sample is drawn
/// independently: the output is then NaN), the range cell's keyed word, the first scatterer
/// pair's index and whether the first scatterer is odd (0 or 1).
struct LatticeSamples {
  const float* w[4];
  const double* inv_2w2;
  const std::uint64_t* cell;
  const std::uint64_t* pair0;
  const std::uint32_t* odd;
  std::size_t samples;
};

/// The speckle power of look offset `look_offset` (added to every pair index) of every sample
/// into out[0 .. samples): the sum over the four scatterers (g1 + i g2) / sqrt 2 of the
/// NormalTable, in float, squared and normalised in double. With AVX2 (checked at run time once)
/// eight samples at a time with the same operations in the same order: bit-identical to the
/// scalar loop (tests/noise_test.cpp compares them).
void lattice_look(const LatticeSamples& s, std::uint64_t look_offset, double* out);

/// The scalar loop alone (the reference, and the path of CPUs without AVX2).
void lattice_look_scalar(const LatticeSamples& s, std::uint64_t look_offset, double* out);

/// Whether lattice_look uses the AVX2 path: the CPU has AVX2 and the path is not switched off.
bool lattice_simd_active();
/// Switches the AVX2 path off (false) or back on where the CPU has it (true); for tests and
/// benchmarks. The environment variable SONARSYNTH_SCALAR=1 switches it off at start-up.
void set_lattice_simd(bool allowed);

}  // namespace sonarsynth
