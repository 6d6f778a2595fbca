// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// Output number `key` of the SplitMix64 generator with state `seed`: mix(seed + (key + 1) gamma)
/// (same paper; the generator's own construction, which passes BigCrush for consecutive keys).
/// One multiply and one splitmix64 per 64 keyed random bits, against two for hash_combine.
constexpr std::uint64_t splitmix_stream(std::uint64_t seed, std::uint64_t key) {
  return splitmix64(seed + key * 0x9e3779b97f4a7c15ULL);
}

/// Output number `key` of the wyrand generator with state `seed` (Wang Yi's public-domain
/// wyhash/wyrand): s = seed + key * 0xa0761d6478bd642f (a Weyl sequence, as splitmix_stream's),
/// then the 128-bit product s (s ^ 0xe7037ed1a0b428db) folded by the xor of its halves. One
/// 64 x 64 -> 128-bit multiply per 64 random bits instead of splitmix_stream's three multiplies
/// and three xor-shifts; for the most numerous keyed words of a ping, the along-track
/// lattice's scatterers and the thermal and receiver noise per sample and look
/// (tests/noise_test.cpp checks the words' 16-bit fields and the speckle built from them).
inline std::uint64_t wyrand_stream(std::uint64_t seed, std::uint64_t key) {
  __extension__ typedef unsigned __int128 U128;
  const std::uint64_t x = seed + key * 0xa0761d6478bd642fULL;
  const U128 t = static_cast<U128>(x) * (x ^ 0xe7037ed1a0b428dbULL);
  return static_cast<std::uint64_t>(t >> 64) ^ static_cast<std::uint64_t>(t);
}

/// 64 random bits from 32 (the high half of `bits`), for UnitGammaTable and
/// cos_uniform_phase_from_bits: the high 32 bits kept, bit 31 set (the midpoint of the 2^-32 cell
/// the 32 bits select, so that the derived uniform is unbiased), the rest 0.
constexpr std::uint64_t high32_midpoint(std::uint64_t bits) {
  return (bits & 0xffffffff00000000ULL) | 0x80000000ULL;
}

/// Uniform double in [0, 1) from the top 53 bits of a 64-bit word.
/// (The shifted word fits in int64: the signed conversion is one instruction on x86-64.)
constexpr double uniform_from_bits(std::uint64_t bits) {
  return static_cast<double>(static_cast<std::int64_t>(bits >> 11)) * 0x1.0p-53;
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

/// sin(x) for |x| <= pi/2 by its Taylor polynomial to x^19 (Horner in x^2): the first omitted
/// term bounds the error, (pi/2)^21 / 21! < 3e-16.
inline double sin_taylor_half_period(double x) {
  // (-1)^j / (2j + 1)!, j = 0 .. 9.
  constexpr double c[10] = {1.0,
                            -1.0 / 6.0,
                            1.0 / 120.0,
                            -1.0 / 5040.0,
                            1.0 / 362880.0,
                            -1.0 / 39916800.0,
                            1.0 / 6227020800.0,
                            -1.0 / 1307674368000.0,
                            1.0 / 355687428096000.0,
                            -1.0 / 121645100408832000.0};
  const double x2 = x * x;
  double p = c[9];
  for (int j = 8; j >= 0; --j) p = p * x2 + c[j];
  return x * p;
}

/// cos(phi) of a uniform phase phi ~ U(0, 2 pi) from 64 random bits, by its equivalent in
/// distribution sin(pi z), z ~ U(-1/2, 1/2) (arcsine law), without a libm call.
inline double cos_uniform_phase_from_bits(std::uint64_t bits) {
  const double z = uniform_from_bits(bits) - 0.5;
  return sin_taylor_half_period(3.14159265358979323846 * z);
}

/// Standard normal variates from 16 random bits: the 2^16 cells of equal probability between
/// the quantiles Phi^-1(k / 2^16), each represented by its conditional mean
/// 2^16 (phi(a_k) - phi(a_k+1)) (the discretisation keeps the mean 0 exactly, by symmetry), scaled
/// by the one factor (1 + ~1e-6) that makes the second moment exactly 1; stored as float.
/// A circular complex Gaussian of unit power is (g1 + i g2) / sqrt(2) from two of them: one load
/// each, no interpolation, no branch. Tails cut at |g| ~ 4.3 (probability 2^-16 beyond the last
/// cell's mean); tested cell by cell against the exact law (tests/noise_test.cpp).
class NormalTable {
 public:
  static constexpr unsigned kBits = 16;
  static constexpr std::size_t kCells = std::size_t{1} << kBits;
  /// The process-wide table (built on first use, thread-safe).
  static const NormalTable& get();
  /// The variate of the low 16 bits of `bits`.
  float operator()(std::uint32_t bits) const { return table_[bits & (kCells - 1)]; }
  /// The cell's lower edge Phi^-1(k / 2^16) (-inf for k = 0, +inf for k = kCells), for tests.
  double edge(std::size_t k) const { return edge_[k]; }
  /// The table's scale factor (the unscaled second moment is 1 / scale^2), for tests.
  double scale() const { return scale_; }
  /// Standard normal density and upper tail, for the table's construction and its tests.
  static double density(double x);
  static double upper_tail(double x);

 private:
  NormalTable();
  std::vector<float> table_;
  std::vector<double> edge_;
  double scale_ = 1.0;
};

/// Gamma(shape, scale = 1) by Marsaglia & Tsang, "A simple method for generating gamma
/// variables", ACM TOMS 26(3):363-372, 2000; for shape < 1 the boost Gamma(shape + 1) * U^(1/shape)
/// from the same paper. Keyed: uses streams stream, stream + 1, ... (at most 4 per attempt).
/// shape must be > 0.
double keyed_gamma(double shape, std::uint64_t seed, std::uint64_t key, std::uint64_t stream);

/// Regularized incomplete gamma functions P(a, x) = gamma(a, x) / Gamma(a) and
/// Q(a, x) = 1 - P(a, x), a > 0, x >= 0: series for x < a + 1, Lentz continued fraction
/// otherwise (Press, Teukolsky, Vetterling & Flannery, Numerical Recipes, 3rd ed., 2007, §6.2).
/// Relative accuracy ~1e-15 for a <= UnitGammaTable::kMaxShape.
double regularized_gamma_p(double a, double x);
double regularized_gamma_q(double a, double x);

/// Inverse of the regularized incomplete gamma function: the x >= 0 with P(a, x) = p, where
/// q = 1 - p is passed too so that upper-tail quantiles keep full relative precision (the
/// residual is taken in P when p <= 1/2, in Q otherwise). Safeguarded Newton iteration
/// (bracketing + bisection fallback) to relative tolerance ~1e-14. a > 0, 0 <= p <= 1.
double inverse_regularized_gamma(double a, double p, double q);

/// Unit-mean Gamma(shape, 1/shape) variates (Exp(1) for shape = 1) from 64 random bits by a
/// tabulated inverse CDF (inversion method, Devroye, "Non-Uniform Random Variate Generation",
/// 1986, §II.2): the top kIndexBits bits choose one of kBins equiprobable bins, the low 52 bits
/// the position frac in (0, 1) inside it, and the bin's quantile is approximated by the
/// quadratic through its exact end quantiles x_k, x_{k+1} whose mean over frac is the bin's exact
/// conditional mean, kBins (P(a+1, x_{k+1}) - P(a+1, x_k)) (unit-mean scale): so the
/// distribution is continuous, every bin has probability exactly 1/kBins and the mean is exact.
/// The first and last bins (unbounded density near 0 for shape < 1, the infinite upper tail) are
/// inverted exactly with inverse_regularized_gamma. The error against the exact distribution is
/// bounded in tests/noise_test.cpp (KS distance < 1e-5, moments).
class UnitGammaTable {
 public:
  static constexpr unsigned kIndexBits = 12;
  static constexpr std::size_t kBins = std::size_t{1} << kIndexBits;
  /// Largest tabulated shape (the build cost grows with sqrt(shape)); callers use keyed_gamma
  /// beyond it.
  static constexpr double kMaxShape = 1000.0;

  /// Builds the table (~ms). 0 < shape <= kMaxShape, else std::invalid_argument.
  explicit UnitGammaTable(double shape);
  /// Process-wide cache, one table per distinct shape value (thread-safe, built on first use).
  static const UnitGammaTable& get(double shape);

  double shape() const { return shape_; }

  /// The variate for 64 uniform random bits.
  double operator()(std::uint64_t bits) const {
    const std::uint64_t k = bits >> (64 - kIndexBits);
    const std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
    // k = 0 or kBins - 1 (unsigned wrap-around): exact inversion.
    if (k - 1 >= kBins - 2) return tail(k, m);
    const double frac = (static_cast<double>(static_cast<std::int64_t>(m)) + 0.5) * 0x1.0p-52;
    const Bin& b = bins_[k];
    return b.x + frac * (b.d + b.c * (1.0 - frac));
  }

  /// The exact quantile (unit mean) at probability p = (k + frac) / kBins, for tests.
  double exact_quantile(double p, double q) const;

  /// The bins in float32, structure of arrays (x of bin k at [k], d at [kBins + k], c at
  /// [2 kBins + k]; bins 0 and kBins - 1 unused: operator() inverts them exactly), for the vector
  /// kernels that gather them (48 KiB instead of 96).
  const float* bins_float() const { return bins_float_.data(); }

 private:
  struct Bin {
    double x;  // quantile at the bin's lower edge
    double d;  // x_{k+1} - x_k
    double c;  // quadratic coefficient: value = x + frac (d + c (1 - frac))
  };
  double tail(std::uint64_t k, std::uint64_t m) const;

  double shape_;
  double lgamma_shape_;
  std::vector<Bin> bins_;
  std::vector<float> bins_float_;
};

}  // namespace sonarsynth
