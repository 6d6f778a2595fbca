// SPDX-License-Identifier: MIT
// The speckle keys of a ping side (lib/simulator.cpp): the key of every (ping, side, sample) and
// the key of the seabed cell of each sample's dominant contributor, in vector form (Highway,
// dispatched at run time; every target gives the scalar values bit for bit). Internal.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth::sample_keys {

/// Keys of samples without a seabed contributor carry this bit so they never collide with
/// ground-cell keys.
constexpr std::uint64_t kPingSampleKeyBit = 1ULL << 63;

/// Key of the seabed cell (ix, iy, iz): the three indices packed into 23 + 23 + 16 bits when
/// they fit (+-2^22 and +-2^15 cells: +-210 km and +-1.6 km at 5 cm), scrambled by a bijection
/// of the 62-bit integers (odd multiplies and xor-shifts mod 2^62, the pattern of splitmix64) and
/// tagged with bit 62: distinct cells in that range never share a key, at two multiplies instead
/// of four mixes; beyond it the chained hash of the three (bit 62 clear). Bit 63 is clear: never
/// a (ping, sample) key.
inline std::uint64_t ground_cell_key(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
  constexpr std::int64_t kXy = std::int64_t{1} << 22, kZ = std::int64_t{1} << 15;
  constexpr std::uint64_t kMask62 = (std::uint64_t{1} << 62) - 1;
  const auto ux = static_cast<std::uint64_t>(ix), uy = static_cast<std::uint64_t>(iy),
             uz = static_cast<std::uint64_t>(iz);
  if (ix >= -kXy && ix < kXy && iy >= -kXy && iy < kXy && iz >= -kZ && iz < kZ) {
    std::uint64_t x = ((ux & 0x7fffffULL) << 39) | ((uy & 0x7fffffULL) << 16) | (uz & 0xffffULL);
    x = (x * 0xbf58476d1ce4e5b9ULL) & kMask62;
    x ^= x >> 31;
    x = (x * 0x94d049bb133111ebULL) & kMask62;
    x ^= x >> 29;
    return (std::uint64_t{1} << 62) | x;
  }
  return (kMask62 & hash_combine(hash_combine(ux, uy), uz));
}

/// Where a side's ground positions are: sample i's contributor lies at (nx, ny) + gy_i (dx, dy)
/// (gy the beam-plane ground range, metres) and height gz_i; cells of 1 / inv_cell metres.
struct CellFrame {
  double nx = 0.0, ny = 0.0, dx = 0.0, dy = 1.0, inv_cell = 1.0;
};

/// keys[i] = kPingSampleKeyBit | splitmix64(h ^ sample_hash[i]) >> 1 for i < n, h =
/// hash_combine(ping, side): with sample_hash[i] = splitmix64(i), the key of (ping, side, i).
void ping_keys(std::uint64_t h, const std::uint64_t* sample_hash, std::size_t n,
               std::uint64_t* keys);

/// The seabed cell key of samples whose class is seabed or object: ground_cell_key of the floors
/// of ((nx + gy dx) inv_cell, (ny + gy dy) inv_cell, gz inv_cell); the other samples take
/// noise_keys[i]. keys may alias noise_keys.
void ground_cell_keys(const CellFrame& f, const SampleClass* cls, const double* gy,
                      const double* gz, const std::uint64_t* noise_keys, std::size_t n,
                      std::uint64_t* keys);

/// The seabed cell (ix, iy, iz) of a sample: the floors of its position over the cell size.
struct Cell {
  std::int64_t ix = 0, iy = 0, iz = 0;
  bool operator==(const Cell&) const = default;
};
inline Cell cell_at(const CellFrame& f, double gy, double gz) {
  const double qx = (f.nx + gy * f.dx) * f.inv_cell, qy = (f.ny + gy * f.dy) * f.inv_cell;
  const double qz = gz * f.inv_cell;
  // floor as int64 for |q| < 2^62 (truncation, minus one for negative non-integers); beyond,
  // std::floor and the conversion.
  const auto floor_to_int = [](double x) {
    if (!(std::abs(x) < 0x1p62)) return static_cast<std::int64_t>(std::floor(x));
    const auto i = static_cast<std::int64_t>(x);
    return static_cast<double>(i) > x ? i - 1 : i;
  };
  return {floor_to_int(qx), floor_to_int(qy), floor_to_int(qz)};
}

/// The scalar reference of ground_cell_keys (one sample).
inline std::uint64_t ground_cell_key_at(const CellFrame& f, double gy, double gz) {
  const Cell c = cell_at(f, gy, gz);
  return ground_cell_key(c.ix, c.iy, c.iz);
}

}  // namespace sonarsynth::sample_keys
