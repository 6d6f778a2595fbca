// SPDX-License-Identifier: MIT
// Speckle / texture / paper-noise statistics (docs/physics.md §1.6, §3.10): moments within
// 3 standard errors (delta method from the theoretical moments), KS against Exp(1).
#include "sonarsynth/noise.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/sensor_effects.hpp"

namespace sonarsynth {
namespace {

constexpr double kPiT = 3.14159265358979323846;
constexpr std::size_t kN = 200000;

std::vector<std::uint64_t> iota_keys(std::size_t n, std::uint64_t offset = 0) {
  std::vector<std::uint64_t> k(n);
  std::iota(k.begin(), k.end(), offset);
  return k;
}

struct Moments {
  double m1, m2;
};
Moments moments(const std::vector<double>& v) {
  double s1 = 0, s2 = 0;
  for (double x : v) {
    s1 += x;
    s2 += x * x;
  }
  const double n = static_cast<double>(v.size());
  return {s1 / n, s2 / n};
}

// Standard error of SI = m2/m1^2 - 1 (delta method) from the raw moments mu1..mu4.
double si_standard_error(double mu1, double mu2, double mu3, double mu4, double n) {
  const double var1 = mu2 - mu1 * mu1, var2 = mu4 - mu2 * mu2, cov = mu3 - mu1 * mu2;
  const double d1 = -2.0 * mu2 / (mu1 * mu1 * mu1), d2 = 1.0 / (mu1 * mu1);
  return std::sqrt((d1 * d1 * var1 + d2 * d2 * var2 + 2.0 * d1 * d2 * cov) / n);
}

std::vector<double> speckled(double mean, double nu, double thermal, std::uint64_t seed) {
  std::vector<double> v(kN, mean);
  const std::vector<std::uint64_t> keys = iota_keys(kN), noise_keys = iota_keys(kN, 1u << 30);
  std::vector<double> nus;
  if (nu > 0) nus.assign(kN, nu);
  apply_speckle_noise(SpeckleNoise{thermal, seed}, keys, noise_keys, nus, v);
  return v;
}

TEST(SpeckleNoise, ExponentialMeanAndScintillationIndex) {
  const double mean = 2.5;
  const std::vector<double> v = speckled(mean, 0.0, 0.0, 1);
  const Moments m = moments(v);
  const double n = static_cast<double>(kN);
  EXPECT_NEAR(m.m1, mean, 3.0 * mean / std::sqrt(n));
  // Exp(1): moments k!; SE of SI = 2 / sqrt(N).
  const double si = m.m2 / (m.m1 * m.m1) - 1.0;
  EXPECT_NEAR(si, 1.0, 3.0 * si_standard_error(1, 2, 6, 24, n));
}

TEST(SpeckleNoise, KDistributionScintillationIndex) {
  for (const double nu : {0.7, 2.0, 5.0}) {
    const std::vector<double> v = speckled(1.0, nu, 0.0, 7);
    const Moments m = moments(v);
    const double n = static_cast<double>(kN);
    // I = T X, T ~ Gamma(nu, 1/nu), X ~ Exp(1): E[I^k] = k! Gamma(nu + k) / (Gamma(nu) nu^k).
    auto mu = [&](int k) {
      double t = 1.0;
      for (int j = 0; j < k; ++j) t *= (nu + j) / nu;
      return std::tgamma(k + 1.0) * t;
    };
    EXPECT_NEAR(m.m1, 1.0, 3.0 * std::sqrt((mu(2) - 1.0) / n)) << nu;
    const double si = m.m2 / (m.m1 * m.m1) - 1.0;
    EXPECT_NEAR(si, 1.0 + 2.0 / nu, 3.0 * si_standard_error(mu(1), mu(2), mu(3), mu(4), n)) << nu;
  }
}

TEST(SpeckleNoise, AmplitudeRatioDbBiasAndKolmogorovSmirnov) {
  const std::vector<double> v = speckled(1.0, 0.0, 0.0, 3);
  const double n = static_cast<double>(kN);
  // Amplitude: Rayleigh, mean/std = sqrt(pi/4) / sqrt(1 - pi/4) = 1.913.
  double a1 = 0, a2 = 0, db = 0;
  for (double x : v) {
    a1 += std::sqrt(x);
    a2 += x;
    db += 10.0 * std::log10(x);
  }
  a1 /= n;
  a2 /= n;
  db /= n;
  const double ratio = a1 / std::sqrt(a2 - a1 * a1);
  const double want_ratio = std::sqrt(kPiT / 4) / std::sqrt(1 - kPiT / 4);
  EXPECT_NEAR(want_ratio, 1.913, 1e-3);
  // Delta method for g(m1, m2) = m1 / sqrt(m2 - m1^2), Rayleigh (E[A^2] = 1) raw moments.
  const double r1 = std::sqrt(kPiT) / 2, r2 = 1.0, r3 = 3.0 * std::sqrt(kPiT) / 4, r4 = 2.0;
  const double s = std::sqrt(r2 - r1 * r1);
  const double d1 = 1.0 / s + r1 * r1 / (s * s * s), d2 = -0.5 * r1 / (s * s * s);
  const double se = std::sqrt(
      (d1 * d1 * (r2 - r1 * r1) + d2 * d2 * (r4 - r2 * r2) + 2.0 * d1 * d2 * (r3 - r1 * r2)) / n);
  EXPECT_NEAR(ratio, want_ratio, 3.0 * se);
  // dB-domain mean of single-look speckle: -10 gamma / ln 10 = -2.507 dB; std 5.57 dB.
  const double euler_gamma = 0.57721566490153286;
  EXPECT_NEAR(db, -10.0 * euler_gamma / std::log(10.0), 3.0 * 5.57 / std::sqrt(n));
  // Kolmogorov–Smirnov against Exp(1) at the 1 % level (D sqrt(N) < 1.63) for 5 seeds: a
  // correct generator fails for 2 or more of them with probability ~1e-3.
  int failures = 0;
  for (std::uint64_t seed = 0; seed < 5; ++seed) {
    std::vector<double> sorted = speckled(1.0, 0.0, 0.0, seed);
    std::sort(sorted.begin(), sorted.end());
    double d = 0.0;
    for (std::size_t i = 0; i < kN; ++i) {
      const double cdf = 1.0 - std::exp(-sorted[i]);
      d = std::max({d, std::abs(cdf - static_cast<double>(i) / n),
                    std::abs(cdf - static_cast<double>(i + 1) / n)});
    }
    if (d * std::sqrt(n) >= 1.63) ++failures;
  }
  EXPECT_LE(failures, 1);
}

TEST(SpeckleNoise, ThermalNoiseAddsPowerBeforeDetection) {
  const double mean = 1.0, noise_power = 0.5;
  const std::vector<double> v = speckled(mean, 0.0, noise_power, 11);
  const Moments m = moments(v);
  const double total = mean + noise_power;
  // Sum of two independent circular Gaussians: still exponential, mean I + N.
  EXPECT_NEAR(m.m1, total, 3.0 * total / std::sqrt(static_cast<double>(kN)));
  EXPECT_NEAR(m.m2 / (m.m1 * m.m1) - 1.0, 1.0,
              3.0 * si_standard_error(1, 2, 6, 24, static_cast<double>(kN)));
  // Zero signal: pure noise, still exponential with mean N.
  const std::vector<double> z = speckled(0.0, 0.0, noise_power, 12);
  EXPECT_NEAR(moments(z).m1, noise_power, 3.0 * noise_power / std::sqrt(static_cast<double>(kN)));
}

TEST(SpeckleNoise, KeyedNotSequentialBitIdenticalInAnyChunking) {
  std::vector<double> whole(1000, 1.0);
  std::vector<std::uint64_t> keys = iota_keys(1000, 5000), nkeys = iota_keys(1000, 9000);
  const SpeckleNoise sn{0.1, 42};
  apply_speckle_noise(sn, keys, nkeys, {}, whole);
  // Processed in reversed halves: same values per key.
  std::vector<double> parts(1000, 1.0);
  std::span<double> all(parts);
  std::span<const std::uint64_t> k(keys), nk(nkeys);
  apply_speckle_noise(sn, k.subspan(500), nk.subspan(500), {}, all.subspan(500));
  apply_speckle_noise(sn, k.first(500), nk.first(500), {}, all.first(500));
  EXPECT_EQ(whole, parts);
  // Frozen per location: the same scatterer key gives the same speckle in another "ping"
  // (thermal noise off), a different seed gives different values.
  std::vector<double> a(1, 1.0), b(1, 1.0), c(1, 1.0);
  const std::uint64_t key = 123456789, ka = 1, kb = 2;
  apply_speckle_noise(SpeckleNoise{0.0, 42}, std::span(&key, 1), std::span(&ka, 1), {}, a);
  apply_speckle_noise(SpeckleNoise{0.0, 42}, std::span(&key, 1), std::span(&kb, 1), {}, b);
  apply_speckle_noise(SpeckleNoise{0.0, 43}, std::span(&key, 1), std::span(&ka, 1), {}, c);
  EXPECT_EQ(a[0], b[0]);
  EXPECT_NE(a[0], c[0]);
  std::vector<double> bad(3, 1.0);
  EXPECT_THROW(apply_speckle_noise(sn, keys, nkeys, {}, bad), InputError);
}

TEST(KeyedGamma, MeanAndVarianceEqualShape) {
  for (const double shape : {0.5, 1.0, 3.0}) {
    const std::size_t n = 100000;
    double s1 = 0, s2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double g = keyed_gamma(shape, 9, i, 100);
      s1 += g;
      s2 += g * g;
    }
    const double m = s1 / static_cast<double>(n);
    const double var = s2 / static_cast<double>(n) - m * m;
    EXPECT_NEAR(m, shape, 3.0 * std::sqrt(shape / static_cast<double>(n))) << shape;
    // Var of the sample variance of Gamma(k): (mu4 - var^2)/n, mu4 = 3k^2 + 6k (central).
    EXPECT_NEAR(var, shape,
                3.0 * std::sqrt((3.0 * shape * shape + 6.0 * shape - shape * shape) /
                                static_cast<double>(n)))
        << shape;
  }
}

// The tabulated inverse CDF against the exact Gamma distribution, deterministically: on every
// interior bin the table's CDF at value(frac) is (k + frac) / kBins, the exact one is
// P(a, a value(frac)); the first and last bins are exact by construction.
TEST(UnitGammaTable, KolmogorovDistanceMomentsAndTailsAgainstExactGamma) {
  constexpr std::size_t kB = UnitGammaTable::kBins;
  // Gauss–Legendre 5 points on [0, 1] for the moments over frac.
  const double gx[5] = {0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155,
                        0.95308992296933200};
  const double gw[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444,
                        0.23931433524968324, 0.11846344252809454};
  for (const double a : {0.3, 0.7, 1.0, 2.0, 5.0, 20.0, 200.0}) {
    const UnitGammaTable& t = UnitGammaTable::get(a);
    double ks = 0.0, m1 = 0.0, m2 = 0.0;
    for (std::uint64_t k = 1; k + 1 < kB; ++k) {
      double prev = -1.0;
      for (int s = 0; s <= 16; ++s) {
        const std::uint64_t m =
            (std::uint64_t{1} << 52) / 16 * static_cast<std::uint64_t>(s) - (s == 16 ? 1 : 0);
        const std::uint64_t bits = (k << 52) | m;
        const double v = t(bits);
        EXPECT_GE(v, prev);  // monotone in the bits
        prev = v;
        const double frac = (static_cast<double>(m) + 0.5) * 0x1.0p-52;
        const double cdf_table = (static_cast<double>(k) + frac) / static_cast<double>(kB);
        ks = std::max(ks, std::abs(regularized_gamma_p(a, a * v) - cdf_table));
      }
      for (int g = 0; g < 5; ++g) {
        const auto m = static_cast<std::uint64_t>(gx[g] * 0x1.0p52);
        const double v = t((k << 52) | m);
        m1 += gw[g] * v / static_cast<double>(kB);
        m2 += gw[g] * v * v / static_cast<double>(kB);
      }
    }
    // The two exact tail bins: E[X/a; bin] = P(a + 1, .) differences, E[(X/a)^2; bin] likewise
    // with P(a + 2, .) and the factor (a + 1) / a.
    const double lo = a * t.exact_quantile(1.0 / kB, 1.0 - 1.0 / kB);
    const double hi = a * t.exact_quantile(1.0 - 1.0 / kB, 1.0 / kB);
    m1 += regularized_gamma_p(a + 1.0, lo) + regularized_gamma_q(a + 1.0, hi);
    m2 += (a + 1.0) / a * (regularized_gamma_p(a + 2.0, lo) + regularized_gamma_q(a + 2.0, hi));
    // 1.63 / sqrt(N) ~ 3.6e-3 at the tests' N = 2e5: the table is invisible to a KS test below
    // N ~ 1e10 samples.
    EXPECT_LT(ks, 1e-5) << a;
    EXPECT_NEAR(m1, 1.0, 1e-9) << a;  // conditional-mean bins: the mean is exact
    EXPECT_NEAR(m2, 1.0 + 1.0 / a, 1e-6 * (1.0 + 1.0 / a)) << a;
    // Tail bins are the exact quantiles.
    const std::uint64_t last = (std::uint64_t{kB - 1} << 52) | 12345u;
    const double q = (static_cast<double>((std::uint64_t{1} << 52) - 12345u) - 0.5) * 0x1.0p-52 /
                     static_cast<double>(kB);
    EXPECT_DOUBLE_EQ(t(last), t.exact_quantile(1.0 - q, q)) << a;
    EXPECT_NEAR(regularized_gamma_q(a, a * t(last)), q, 1e-12 * q) << a;
  }
  EXPECT_THROW(UnitGammaTable(0.0), std::invalid_argument);
}

TEST(UnitGammaTable, InverseRegularizedGammaRoundTripsIntoTheTails) {
  for (const double a : {0.1, 0.5, 1.0, 3.0, 20.0, 1000.0}) {
    for (const double p : {1e-18, 1e-9, 1e-3, 0.3, 0.5}) {
      const double x = inverse_regularized_gamma(a, p, 1.0 - p);
      // (ln P and ln Q carry ~1e-13 relative rounding at a = 1000: exponent ~ a ln x.)
      EXPECT_NEAR(regularized_gamma_p(a, x), p, 1e-11 * p) << a << " " << p;
      const double y = inverse_regularized_gamma(a, 1.0 - p, p);  // upper tail, q = p
      EXPECT_NEAR(regularized_gamma_q(a, y), p, 1e-11 * p) << a << " " << p;
    }
  }
  // Exp(1): closed form.
  EXPECT_NEAR(inverse_regularized_gamma(1.0, 1.0 - 1e-15, 1e-15), -std::log(1e-15), 1e-12);
}

TEST(SpeckleNoise, PhasePolynomialMatchesSine) {
  double worst = 0.0;
  for (int i = -100000; i <= 100000; ++i) {
    const double x = 0.5 * kPiT * i / 100000.0;
    worst = std::max(worst, std::abs(sin_taylor_half_period(x) - std::sin(x)));
  }
  EXPECT_LT(worst, 1e-15);
}

// The tabulated standard normal against the exact law in every one of its 2^16 cells: each edge
// has the upper tail Q(x) = erfc(x / sqrt 2) / 2 it should (k / 2^16), each value (unscaled) lies
// inside its cell and equals the cell's conditional mean, checked in 64 cells against an
// independent Simpson quadrature of x phi(x); the table is odd and increasing, E[g] = 0,
// E[g^2] = 1 (float rounding), E[g^4] = 3 up to the discretisation (the conditional means lose
// the within-cell spread: a few 1e-4 in the tails).
TEST(NormalTable, EveryCellAgainstTheExactLaw) {
  const NormalTable& t = NormalTable::get();
  const std::size_t n = NormalTable::kCells;
  EXPECT_NEAR(t.scale(), 1.0, 1e-5);
  double worst_edge = 0.0, s1 = 0.0, s2 = 0.0, s4 = 0.0;
  bool inside = true, monotone = true, odd = true;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      const double q = static_cast<double>(n - k) / static_cast<double>(n);
      // Relative error of the tail probability at the edge, from the smaller tail.
      const double x = t.edge(k);
      const double err = x >= 0.0
                             ? std::abs(0.5 * std::erfc(x / std::sqrt(2.0)) / q - 1.0)
                             : std::abs(0.5 * std::erfc(-x / std::sqrt(2.0)) / (1.0 - q) - 1.0);
      worst_edge = std::max(worst_edge, err);
    }
    const double g = t(static_cast<std::uint32_t>(k));
    const double unscaled = g / t.scale();
    inside = inside && unscaled >= t.edge(k) - 1e-6 && unscaled <= t.edge(k + 1) + 1e-6;
    if (k > 0) monotone = monotone && g >= double{t(static_cast<std::uint32_t>(k - 1))};
    odd = odd && g == -double{t(static_cast<std::uint32_t>(n - 1 - k))};
    s1 += g;
    s2 += g * g;
    s4 += g * g * g * g;
  }
  EXPECT_LT(worst_edge, 1e-12);
  EXPECT_TRUE(inside);
  EXPECT_TRUE(monotone);
  EXPECT_TRUE(odd);
  const double cells = static_cast<double>(n);
  EXPECT_NEAR(s1 / cells, 0.0, 1e-12);
  EXPECT_NEAR(s2 / cells, 1.0, 1e-6);
  EXPECT_NEAR(s4 / cells, 3.0, 2e-3);
  // Conditional means of finite cells by Simpson's rule (2,000 intervals) of x phi(x) / (1 / n).
  for (std::size_t k = 1; k + 1 < n; k += 1031) {
    const double a = t.edge(k), b = t.edge(k + 1);
    const int m = 2000;
    const double h = (b - a) / m;
    double sum = 0.0;
    for (int i = 0; i <= m; ++i) {
      const double x = a + h * i;
      const double f = x * std::exp(-0.5 * x * x) / std::sqrt(2.0 * kPiT);
      sum += (i == 0 || i == m ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0)) * f;
    }
    const double mean = sum * h / 3.0 * cells;
    EXPECT_NEAR(t(static_cast<std::uint32_t>(k)) / t.scale(), mean, 1e-6 * (1.0 + std::abs(mean)))
        << k;
  }
  // Only the low 16 bits count.
  EXPECT_EQ(t(0x1234u), t(0xabcd1234u));
}

// wyrand_stream against its definition computed independently with 32-bit limbs (the 128-bit
// product by schoolbook multiplication), and the 16-bit fields the along-track lattice reads
// (NormalTable indices) of consecutive keys: uniform (chi-square over 256 classes of each
// field's top byte, below the 0.1 % point 330.5 of chi^2(255)) and uncorrelated between
// consecutive keys (within 4 / sqrt(N)).
TEST(KeyedRandom, WyrandStreamMatchesItsDefinitionAndItsFieldsAreUniform) {
  const auto reference = [](std::uint64_t seed, std::uint64_t key) {
    const std::uint64_t x = seed + key * 0xa0761d6478bd642fULL;
    const std::uint64_t y = x ^ 0xe7037ed1a0b428dbULL;
    const std::uint64_t a[2] = {x & 0xffffffffULL, x >> 32}, b[2] = {y & 0xffffffffULL, y >> 32};
    std::uint64_t limb[4] = {0, 0, 0, 0};  // 32-bit limbs of the product, carries propagated
    for (int i = 0; i < 2; ++i) {
      std::uint64_t carry = 0;
      for (int j = 0; j < 2; ++j) {
        const std::uint64_t p = a[i] * b[j];  // < 2^64
        const std::uint64_t lo = (p & 0xffffffffULL) + limb[i + j] + carry;
        limb[i + j] = lo & 0xffffffffULL;
        carry = (p >> 32) + (lo >> 32);
      }
      limb[i + 2] += carry;
    }
    const std::uint64_t low = limb[0] | (limb[1] << 32), high = limb[2] | (limb[3] << 32);
    return low ^ high;
  };
  for (std::uint64_t k = 0; k < 1000; ++k) {
    const std::uint64_t seed = splitmix64(k), key = splitmix64(~k) >> (k % 40);
    ASSERT_EQ(wyrand_stream(seed, key), reference(seed, key)) << k;
  }
  const std::size_t n = 1 << 18;
  for (const std::uint64_t seed : {std::uint64_t{0}, splitmix64(5), splitmix64(6)}) {
    for (int field = 0; field < 4; ++field) {
      std::vector<double> count(256, 0.0);
      double m = 0.0, c = 0.0;
      double prev = 0.0;
      for (std::size_t k = 0; k < n; ++k) {
        const auto v = static_cast<std::uint32_t>(wyrand_stream(seed, k) >> (16 * field)) & 0xffffu;
        count[v >> 8] += 1.0;
        const double u = (static_cast<double>(v) + 0.5) / 65536.0 - 0.5;  // mean 0, var 1/12
        m += u;
        if (k > 0) c += u * prev;
        prev = u;
      }
      double chi2 = 0.0;
      const double expected = static_cast<double>(n) / 256.0;
      for (const double x : count) chi2 += (x - expected) * (x - expected) / expected;
      EXPECT_LT(chi2, 330.5) << seed << " " << field;
      const double nn = static_cast<double>(n);
      EXPECT_NEAR(m / nn * std::sqrt(12.0), 0.0, 4.0 / std::sqrt(nn)) << seed << " " << field;
      EXPECT_NEAR(c / nn * 12.0, 0.0, 4.0 / std::sqrt(nn)) << seed << " " << field;
    }
  }
}

// The along-track speckle field (docs/physics.md §1.6) of pings far apart on the lattice:
// unit-mean exponential per sample (KS at the 1 % level, E[S] = 1, E[S^2] = 2 within 4 standard
// errors), its looks independent (correlation within 4 / sqrt(N)), and the looks computed
// together equal the looks computed one at a time.
TEST(AlongTrackSpeckle, ExponentialOfUnitMeanAndIndependentLooks) {
  AlongTrackField f;
  f.key = 7;
  f.seed = 99;
  f.sample_spacing_m = 0.02;
  f.beam_3db_rad = 0.01;
  const std::size_t samples = 20000;
  std::vector<double> s0, s1, v, one;
  AlongTrackTable table;
  for (int ping = 0; ping < 10; ++ping) {
    f.along_track_m = 1000.0 * ping + 0.37 * ping;
    along_track_speckle_looks(f, samples, 0, 2, table, v);
    s0.insert(s0.end(), v.begin(), v.begin() + static_cast<std::ptrdiff_t>(samples));
    s1.insert(s1.end(), v.begin() + static_cast<std::ptrdiff_t>(samples), v.end());
    along_track_speckle(f, samples, 1, table, one);
    EXPECT_TRUE(
        std::equal(one.begin(), one.end(), v.begin() + static_cast<std::ptrdiff_t>(samples)));
  }
  const double n = static_cast<double>(s0.size());
  double m = 0.0, m2 = 0.0, c = 0.0;
  for (std::size_t i = 0; i < s0.size(); ++i) {
    m += s0[i];
    m2 += s0[i] * s0[i];
    c += (s0[i] - 1.0) * (s1[i] - 1.0);
  }
  EXPECT_NEAR(m / n, 1.0, 4.0 / std::sqrt(n));          // Var S = 1
  EXPECT_NEAR(m2 / n, 2.0, 4.0 * std::sqrt(20.0 / n));  // Var S^2 = 24 - 4
  EXPECT_NEAR(c / n, 0.0, 4.0 / std::sqrt(n));
  std::sort(s0.begin(), s0.end());
  double d = 0.0;
  for (std::size_t i = 0; i < s0.size(); ++i) {
    const double cdf = -std::expm1(-s0[i]);
    d = std::max({d, std::abs(cdf - static_cast<double>(i) / n),
                  std::abs(cdf - static_cast<double>(i + 1) / n)});
  }
  EXPECT_LT(d, 1.63 / std::sqrt(n));
  EXPECT_THROW(along_track_speckle_looks(f, 10, 255, 2, table, v), std::invalid_argument);
}

// The default (tables + interference formula) and the reference (Box–Muller + Marsaglia–Tsang)
// samplers: same distribution of K-distributed speckle plus thermal noise (two-sample KS at the
// 1 % level, D < 1.63 sqrt(2 / N)), and the first two moments of I' = |s + n|^2 with T ~ Gamma.
TEST(SpeckleNoise, TablesAndExactSamplersAgreeInDistribution) {
  const double nu = 2.0, noise_power = 0.4;
  std::vector<double> tab(kN, 1.0), ref(kN, 1.0);
  const std::vector<std::uint64_t> keys = iota_keys(kN), nkeys = iota_keys(kN, 1u << 30);
  const std::vector<double> nus(kN, nu);
  apply_speckle_noise(SpeckleNoise{noise_power, 21, SpeckleSampler::tables}, keys, nkeys, nus, tab);
  apply_speckle_noise(SpeckleNoise{noise_power, 22, SpeckleSampler::exact}, keys, nkeys, nus, ref);
  const double n = static_cast<double>(kN);
  // E[I'] = 1 + N; E[I'^2] = 2 E[(T + N)^2] = 2 (1 + 1/nu + 2 N + N^2) (I' | T exponential).
  const double mu1 = 1.0 + noise_power;
  const double mu2 = 2.0 * (1.0 + 1.0 / nu + 2.0 * noise_power + noise_power * noise_power);
  for (const auto* v : {&tab, &ref}) {
    const Moments m = moments(*v);
    EXPECT_NEAR(m.m1, mu1, 3.0 * std::sqrt((mu2 - mu1 * mu1) / n));
  }
  std::sort(tab.begin(), tab.end());
  std::sort(ref.begin(), ref.end());
  double d = 0.0;
  std::size_t i = 0, j = 0;
  while (i < kN && j < kN) {
    if (tab[i] <= ref[j]) {
      ++i;
    } else {
      ++j;
    }
    d = std::max(d, std::abs(static_cast<double>(i) - static_cast<double>(j)) / n);
  }
  EXPECT_LT(d, 1.63 * std::sqrt(2.0 / n));
  // Frozen speckle: the same scatterer key with a different noise key shares A, so two "pings"
  // are positively correlated; without thermal noise they are identical.
  std::vector<double> p1(kN, 1.0), p2(kN, 1.0);
  apply_speckle_noise(SpeckleNoise{noise_power, 5}, keys, nkeys, {}, p1);
  apply_speckle_noise(SpeckleNoise{noise_power, 5}, keys, iota_keys(kN, 1u << 31), {}, p2);
  double c12 = 0.0;
  for (std::size_t k = 0; k < kN; ++k) c12 += p1[k] * p2[k];
  // E[I1 I2] = E[(A + B1)(A + B2)] (cross terms have zero mean) = 2 + 2 N + N^2 for I = 1.
  const double want = 2.0 + 2.0 * noise_power + noise_power * noise_power;
  EXPECT_NEAR(c12 / n, want, 0.05 * want);
}

TEST(PaperNoise, MomentsOfEquationTwo) {
  const double intensity = 4.0, a = 0.3, sigma = 0.2;
  const double n = static_cast<double>(kN);
  std::vector<double> v(kN, intensity);
  apply_paper_noise(PaperNoise{a, sigma, 5}, iota_keys(kN), v);
  const Moments m = moments(v);
  // E[I'] = I (1 + 0) + sigma sqrt(pi/2); Var = I^2 a^2 / 3 + (2 - pi/2) sigma^2.
  const double var = intensity * intensity * a * a / 3.0 + (2.0 - kPiT / 2) * sigma * sigma;
  EXPECT_NEAR(m.m1, intensity + sigma * std::sqrt(kPiT / 2), 3.0 * std::sqrt(var / n));
  // Multiplicative part alone: contrast a / sqrt(3).
  std::vector<double> w(kN, intensity);
  apply_paper_noise(PaperNoise{a, 0.0, 6}, iota_keys(kN), w);
  const Moments mw = moments(w);
  const double contrast = std::sqrt(mw.m2 - mw.m1 * mw.m1) / mw.m1;
  // SE of the sample std of U(-a, a) I: sqrt((mu4/sigma^4 - 1) / (4 N)) relative, mu4/s^4 = 1.8.
  EXPECT_NEAR(contrast, a / std::sqrt(3.0), 3.0 * (a / std::sqrt(3.0)) * std::sqrt(0.8 / (4 * n)));
  EXPECT_THROW(apply_paper_noise(PaperNoise{1.5, 0.0, 0}, iota_keys(kN), w), InputError);
}

// The paper's reading u ~ U(0, g') with variance gamma: g' = sqrt(12 gamma), E[u] = g' / 2,
// Var[u] = gamma, u in [0, g'] (a = sqrt(3 gamma), from zero).
TEST(PaperNoise, UniformFromZeroHasThePapersVarianceGamma) {
  const double intensity = 2.0, gamma = 0.03;
  const double g = std::sqrt(12.0 * gamma);  // 0.6
  const double n = static_cast<double>(kN);
  std::vector<double> v(kN, intensity);
  PaperNoise pn{std::sqrt(3.0 * gamma), 0.0, 9};
  pn.uniform_from_zero = true;
  apply_paper_noise(pn, iota_keys(kN), v);
  const Moments m = moments(v);
  // I' = I (1 + u): mean I (1 + g/2), variance I^2 gamma.
  const double var = intensity * intensity * gamma;
  EXPECT_NEAR(m.m1, intensity * (1.0 + 0.5 * g), 4.0 * std::sqrt(var / n));
  const double sample_var = m.m2 - m.m1 * m.m1;
  // SE of a sample variance: sqrt((mu4 / sigma^4 - 1) / N) relative, mu4 / sigma^4 = 1.8.
  EXPECT_NEAR(sample_var, var, 4.0 * var * std::sqrt(0.8 / n));
  // Support [I, I (1 + g)], filled to its ends; the quartiles of a uniform.
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  EXPECT_GE(*lo, intensity);
  EXPECT_LE(*hi, intensity * (1.0 + g));
  EXPECT_LT(*lo, intensity * (1.0 + 1e-3 * g));
  EXPECT_GT(*hi, intensity * (1.0 + (1.0 - 1e-3) * g));
  const double below_quarter =
      static_cast<double>(std::count_if(
          v.begin(), v.end(), [&](double x) { return x < intensity * (1.0 + 0.25 * g); })) /
      n;
  EXPECT_NEAR(below_quarter, 0.25, 4.0 * std::sqrt(0.25 * 0.75 / n));
  // The same variance as the zero-mean reading U(-a, a) with a = sqrt(3 gamma), shifted by a:
  // the same keys give exactly I a more.
  std::vector<double> w(kN, intensity);
  pn.uniform_from_zero = false;
  apply_paper_noise(pn, iota_keys(kN), w);
  for (std::size_t i = 0; i < kN; i += 997) {
    EXPECT_NEAR(v[i] - w[i], intensity * pn.uniform_half_width, 1e-12) << i;
  }
}

}  // namespace
}  // namespace sonarsynth
