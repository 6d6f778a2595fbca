// SPDX-License-Identifier: MIT
// The along-track scatterer lattice of along_track_speckle (docs/physics.md §1.6): the geometry
// of a block of samples (the three scatterers nearest the ping, their weights and keys), the
// scatterers themselves (a keyed counter hash and Box-Muller by arithmetic), and the vector
// kernel that sums them per look (lib/along_track_lattice.cpp, AVX-512, AVX2 or the portable
// scalar target).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarsynth/counter_hash.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/sensor_effects.hpp"

namespace sonarsynth::lattice {

// Lattice step in units of the weight's standard deviation.
constexpr double kStep = 1.5;
// Salt of the along-track scatterer lattice.
constexpr std::uint64_t kFieldSalt = 0xa10e7a0c5ca77e45ULL;
constexpr int kMaxLooks = 256;
// Scatterers summed per sample: the three nearest the ping (the next carries at most 0.55 % of
// the weight power, docs/physics.md §1.6).
constexpr int kKept = 3;
// The weights' width is the footprint's sw times this factor: with three scatterers the
// correlation of pings d apart falls up to 0.021 below the continuous exp(-d^2 / (2 sw^2)) (at
// d = 1.5 sw); 3 % wider weights bring it within 0.005 of it for every d (docs/physics.md §1.6).
constexpr double kWidthFactor = 1.03;
// Samples per block of the kernel (a multiple of every target's lane count).
constexpr std::size_t kBlock = 256;
// Odd multiplier folding the high half of a lattice index into the scatterer's key.
constexpr std::uint32_t kHighMul = 0x9e3779b9U;

// The keyed word of the lattice line (survey line and side).
inline std::uint64_t line_word(const AlongTrackField& f) {
  return hash_combine(splitmix64(f.seed ^ kFieldSalt), f.key);
}

// The counter-hash stream of a line's scatterers.
inline counter_hash::Stream line_stream(std::uint64_t line) {
  return counter_hash::Stream::of(line);
}

// The key of scatterer m of sample i: the low half of m, and the sample index plus an odd
// multiple of the high half of m (distinct m of one sample never share a key; scatterer m + k's
// key is the low half plus k, the high half plus kHighMul on a carry).
inline std::uint32_t key_lo(std::int64_t m) {
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(m));
}
inline std::uint32_t key_hi(std::size_t i, std::int64_t m) {
  return static_cast<std::uint32_t>(i) +
         static_cast<std::uint32_t>(static_cast<std::uint64_t>(m) >> 32) * kHighMul;
}

// The scatterers' words: the key word of scatterer m of sample i (key_word of the line's stream,
// shared by the looks), and look j's word of it (draw number j).
// Magnitude: the low 20 bits of the look's word give u1, the midpoint of one of 2^20 equal
// cells of (0, 1); |z|^2 = -ln(u1) / M is exponential of mean exactly 1 (M, this function, the
// mean of -ln over the 2^20 midpoints: 1 - 3.3e-7; the tail beyond 14.6 is cut, probability
// 5e-7). Phase: the top 12 bits, the midpoint of one of 4096 equal cells of
// (0, 2 pi).
inline double mean_neg_log_midpoints() {
  const double n = 0x1p20;
  // -(1/N) sum_k ln((k + 1/2) / N) = ln N - (ln Gamma(N + 1/2) - ln Gamma(1/2)) / N.
  return std::log(n) - (std::lgamma(n + 0.5) - std::lgamma(0.5)) / n;
}

// Scatterer of look word `w`, the reference in double with std:: maths: a unit circular
// Gaussian sqrt(-ln u1 / M) e^(i phi) (Box-Muller, M = mean_neg_log_midpoints()). The kernel
// computes the same in float: -ln by a polynomial, cos and sin of the phase by quadrant (its top
// two bits) and polynomials on (-pi/4, pi/4).
inline void scatterer_reference(std::uint32_t w, double& re, double& im) {
  const double u1 = (static_cast<double>(w & 0xfffffU) + 0.5) * 0x1p-20;
  const double phi = (static_cast<double>(w >> 20) + 0.5) * (6.283185307179586 * 0x1p-12);
  const double r = std::sqrt(-std::log(u1) / mean_neg_log_midpoints());
  re = r * std::cos(phi);
  im = r * std::sin(phi);
}

// The geometry of one block of samples, shared by the looks: the key of the first kept
// scatterer, and its offset d0 = m_first - u from the ping (in lattice steps, in [-1.5, -0.5];
// scatterer k is d0 + k away); d0 NaN where the lattice does not apply (below the first return,
// pings more than 2.5 footprints apart, a degenerate beam or position, or need <= 0; there the
// key is that of m = 0).
struct Geometry {
  alignas(64) std::uint32_t lo[kBlock];
  alignas(64) std::uint32_t hi[kBlock];
  alignas(64) float d0[kBlock];
  alignas(64) float inv_w2[kBlock];  // written by the kernel: 1 / sum_k w_k^2, NaN where d0 is
};

// What the geometry kernel (GeometryBlock) reads: per sample of the block (from sample i0, n
// samples, a multiple of the widest lane count) 1 / (lattice step) and sw, and the need (null:
// none); the ping's position and spacing, the first return's sample.
struct GeometryArgs {
  const double* inv_step;
  const double* sw;
  const double* need;
  std::size_t i0, n;
  double along_track_m, ping_spacing_m, first_sample;
  Geometry* g;
};

// What the kernel (LatticeBlock) reads and writes: the block's geometry (inv_w2 written), the
// line's stream, the looks (first_look ..), the outputs (re, im of look j at j * stride), and
// 1 / sqrt(2 mean_neg_log_midpoints()).
struct BlockArgs {
  Geometry* g;
  std::size_t n;  // samples of the block, rounded up to the widest lane count
  counter_hash::Stream stream;
  std::uint32_t first_look;
  int looks;
  float* re;
  float* im;
  std::size_t stride;
  float magnitude_scale;
};

// The unnormalised complex sums sum_k w_k z_k of looks first_look .. first_look + looks - 1 of
// `samples` samples of a ping side: look j's in re/im[j * stride + i], stride = samples rounded
// up to kBlock; norm[i] the normalisation (NaN where the lattice does not apply, or need[i] <= 0
// if `need` is given: there re and im are left as they were). Blocks where it applies nowhere
// cost no kernel call. On the SIMD target of simd::active_target() (after
// simd::configure_from_environment()). Returns the number of samples where the lattice applies.
std::size_t look_sums(const AlongTrackField& f, AlongTrackTable& table, std::size_t samples,
                      int first_look, int looks, std::vector<float>& re, std::vector<float>& im,
                      std::vector<double>& norm, const double* need = nullptr);

// The stride of look_sums' outputs.
constexpr std::size_t padded(std::size_t samples) {
  return (samples + kBlock - 1) / kBlock * kBlock;
}

}  // namespace sonarsynth::lattice
