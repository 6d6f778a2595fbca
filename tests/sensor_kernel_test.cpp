// SPDX-License-Identifier: MIT
// The detector stage's vector kernel (lib/sensor_kernel.cpp, docs/physics.md §1.6): its draws
// against their distributions (uniformity, exponential and Rician moments, independence across
// keys, lanes, looks and streams), the documented words, and the AVX-512, AVX2 and scalar paths
// against each other.
#include "sonarsynth/sensor_kernel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "sonarsynth/counter_hash.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/simd.hpp"

namespace sonarsynth {
namespace {

namespace sk = sensor_kernel;
constexpr std::size_t kN = 200000;
constexpr double kPi = 3.14159265358979323846;

// One kernel call: n samples of constant base, gain 1, keys i + key_offset (consecutive: the
// hardest input for a hash), noise keys the same unless given.
struct KernelRun {
  std::size_t n = kN;
  double base = 1.0, thermal = 0.0, floor = 0.0;
  int looks = 1;
  bool max_detector = true;
  std::uint64_t key_offset = 0, noise_key_offset = 0, seed = 7;
  const std::vector<double>* field = nullptr;
  std::vector<double> operator()() const {
    std::vector<std::uint64_t> keys(n), noise_keys(n);
    std::iota(keys.begin(), keys.end(), key_offset);
    std::iota(noise_keys.begin(), noise_keys.end(), noise_key_offset);
    std::vector<double> b(n, base), gain(n, 1.0), out(n);
    sk::DetectorArgs a;
    a.keys = keys.data();
    a.noise_keys = noise_keys.data();
    a.base = b.data();
    a.gain = gain.data();
    a.field = field != nullptr ? field->data() : nullptr;
    a.out = out.data();
    a.n = n;
    a.looks = looks;
    a.max_detector = max_detector;
    a.thermal_power = thermal;
    a.floor_power = floor;
    a.seed = seed;
    sk::detect(a);
    return out;
  }
};

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}
double central(const std::vector<double>& v, int k) {
  const double m = mean(v);
  double s = 0.0;
  for (const double x : v) s += std::pow(x - m, k);
  return s / static_cast<double>(v.size());
}
double correlation(const std::vector<double>& a, const std::vector<double>& b,
                   std::size_t lag = 0) {
  const std::size_t n = std::min(a.size(), b.size()) - lag;
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ma += a[i];
    mb += b[i + lag];
  }
  ma /= static_cast<double>(n);
  mb /= static_cast<double>(n);
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = a[i] - ma, y = b[i + lag] - mb;
    sab += x * y;
    saa += x * x;
    sbb += y * y;
  }
  return sab / std::sqrt(saa * sbb);
}
// Pearson chi-square of values in [0, 1) against the uniform distribution, `bins` bins.
double chi_square_uniform(const std::vector<double>& u, std::size_t bins) {
  std::vector<double> count(bins, 0.0);
  for (const double x : u) {
    count[std::min(bins - 1, static_cast<std::size_t>(x * static_cast<double>(bins)))] += 1.0;
  }
  const double expected = static_cast<double>(u.size()) / static_cast<double>(bins);
  double chi2 = 0.0;
  for (const double c : count) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}
// chi-square with d degrees of freedom stays below d + 6 sqrt(2 d) (a 6-sigma bound: a failure
// is a defect, not chance).
double chi_square_bound(std::size_t dof) {
  const auto d = static_cast<double>(dof);
  return d + 6.0 * std::sqrt(2.0 * d);
}

// Exp(1): mean 1 (sd 1/sqrt n), variance 1 (sd sqrt(8/n)); 5 standard errors.
void expect_exp1(const std::vector<double>& v, const char* what) {
  const double n = static_cast<double>(v.size());
  EXPECT_NEAR(mean(v), 1.0, 5.0 / std::sqrt(n)) << what;
  EXPECT_NEAR(central(v, 2), 1.0, 5.0 * std::sqrt(8.0 / n)) << what;
  // The CDF: exp(-x) is uniform on (0, 1).
  std::vector<double> u(v.size());
  std::transform(v.begin(), v.end(), u.begin(), [](double x) { return std::exp(-x); });
  EXPECT_LT(chi_square_uniform(u, 100), chi_square_bound(99)) << what;
}

TEST(SensorKernel, HashWordsAreUniformOverConsecutiveKeysAndCounters) {
  const counter_hash::Stream s = sk::speckle_stream(3);
  for (std::uint32_t counter : {0u, 1u, 2u}) {
    std::vector<double> u(kN);
    for (std::size_t i = 0; i < kN; ++i) {
      const std::uint32_t h = counter_hash::key_word(s, std::uint64_t{i});
      u[i] = counter_hash::draw(s, h, counter) * 0x1p-32;
    }
    EXPECT_LT(chi_square_uniform(u, 256), chi_square_bound(255)) << counter;
    // Successive keys (the lanes of one vector) and successive counters are uncorrelated.
    EXPECT_LT(std::abs(correlation(u, u, 1)), 5.0 / std::sqrt(double{kN})) << counter;
  }
}

TEST(SensorKernel, SpeckleIsMinusLogOfTheDocumentedWord) {
  KernelRun r;
  r.n = 4099;  // not a multiple of any vector or block length
  r.key_offset = 0xabcdef0123ULL;
  const std::vector<double> out = r();
  const counter_hash::Stream s = sk::speckle_stream(r.seed);
  for (std::size_t i = 0; i < r.n; ++i) {
    const std::uint32_t w = counter_hash::draw(s, counter_hash::key_word(s, r.key_offset + i), 0);
    const double expected = -std::log(static_cast<double>(counter_hash::uniform_open(w)));
    ASSERT_NEAR(out[i], expected, 1e-6 * expected + 1e-7) << i;  // float log
  }
}

TEST(SensorKernel, SpeckleThermalAndFloorDrawsAreExponential) {
  KernelRun speckle;
  expect_exp1(speckle(), "frozen speckle");
  KernelRun thermal;
  thermal.base = 0.0;
  thermal.thermal = 1.0;
  expect_exp1(thermal(), "thermal noise alone (|n|^2)");
  KernelRun floor;
  floor.base = 0.0;
  floor.floor = 1.0;
  expect_exp1(floor(), "receiver floor");
}

// |1 + n|^2, n circular Gaussian of unit power: 2 p is noncentral chi-square with 2 degrees of
// freedom and noncentrality 2, so mean 2, variance 3, third central moment 8 (cumulants
// 2^j (j - 1)! (k + j lambda) / 2^j). Tests the Gaussian pair behind the complex-power form.
TEST(SensorKernel, ThermalNoiseOnAFixedEchoIsRician) {
  const std::vector<double> ones(kN, 1.0);  // the frozen speckle power given: E_s = 1
  KernelRun r;
  r.thermal = 1.0;
  r.field = &ones;
  const std::vector<double> p = r();
  const double n = static_cast<double>(kN);
  EXPECT_NEAR(mean(p), 2.0, 5.0 * std::sqrt(3.0 / n));
  EXPECT_NEAR(central(p, 2), 3.0, 0.06);
  EXPECT_NEAR(central(p, 3), 8.0, 0.5);
  EXPECT_TRUE(std::all_of(p.begin(), p.end(), [](double x) { return x >= 0.0; }));
}

TEST(SensorKernel, DrawsAreIndependentAcrossKeysLanesLooksAndStreams) {
  const double tol = 5.0 / std::sqrt(double{kN});
  KernelRun r;
  r.thermal = 1.0;
  r.floor = 1.0;
  const std::vector<double> all = r();
  // Neighbouring lanes, and the same lane one vector later (4, 8, 16 lanes).
  for (std::size_t lag : {1u, 2u, 4u, 8u, 16u}) {
    EXPECT_LT(std::abs(correlation(all, all, lag)), tol) << lag;
  }
  // Speckle, thermal and floor of the same key (water column: key == noise key) are unrelated.
  KernelRun speckle;
  KernelRun thermal;
  thermal.base = 0.0;
  thermal.thermal = 1.0;
  KernelRun floor;
  floor.base = 0.0;
  floor.floor = 1.0;
  const std::vector<double> s = speckle(), t = thermal(), f = floor();
  EXPECT_LT(std::abs(correlation(s, t)), tol);
  EXPECT_LT(std::abs(correlation(s, f)), tol);
  EXPECT_LT(std::abs(correlation(t, f)), tol);
  // Looks (counters) are independent: the max of 3 Exp(1) has mean 1 + 1/2 + 1/3; the square
  // of the mean of 2 envelopes has mean (1 + (sqrt(pi) / 2)^2) / 2.
  KernelRun max3;
  max3.looks = 3;
  EXPECT_NEAR(mean(max3()), 1.0 + 0.5 + 1.0 / 3.0, 0.01);
  KernelRun mean2;
  mean2.looks = 2;
  mean2.max_detector = false;
  EXPECT_NEAR(mean(mean2()), 0.5 * (1.0 + kPi / 4.0), 0.01);
  // Another seed, another field.
  KernelRun other;
  other.seed = 8;
  EXPECT_LT(std::abs(correlation(s, other())), tol);
}

TEST(SensorKernel, ZeroMeanSamplesGetOnlyThermalAndFloorNoise) {
  // Half the samples shadow (mean 0): their output is that of an all-shadow run, sample for
  // sample (no speckle, same noise), whatever the neighbours.
  const std::size_t n = 5000;
  std::vector<std::uint64_t> keys(n), noise_keys(n);
  std::iota(keys.begin(), keys.end(), 100);
  std::iota(noise_keys.begin(), noise_keys.end(), 9000);
  std::vector<double> mixed(n), shadow(n, 0.0), gain(n, 3.0), out_mixed(n), out_shadow(n);
  for (std::size_t i = 0; i < n; ++i) mixed[i] = (i / 37) % 2 == 0 ? 0.0 : 0.5;
  for (const bool max_detector : {true, false}) {
    sk::DetectorArgs a;
    a.keys = keys.data();
    a.noise_keys = noise_keys.data();
    a.gain = gain.data();
    a.n = n;
    a.looks = 3;
    a.max_detector = max_detector;
    a.thermal_power = 0.25;
    a.floor_power = 0.5;
    a.base = mixed.data();
    a.out = out_mixed.data();
    sk::detect(a);
    a.base = shadow.data();
    a.out = out_shadow.data();
    sk::detect(a);
    for (std::size_t i = 0; i < n; ++i) {
      if (mixed[i] == 0.0) {
        ASSERT_EQ(out_mixed[i], out_shadow[i]) << i;
        ASSERT_GT(out_shadow[i], 0.0) << i;
      }
    }
  }
}

// Inputs that reach every branch: shadows, a lattice field with gaps, both detectors, 1-3
// looks, thermal and floor noise, a length that is no multiple of a vector or block.
std::vector<std::vector<double>> all_modes() {
  const std::size_t n = 3001;
  std::vector<std::uint64_t> keys(n), noise_keys(n);
  std::vector<double> base(n), gain(n), field(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = splitmix64(i / 4);  // runs of one seabed cell
    noise_keys[i] = splitmix64(i + 0x1000000);
    base[i] = (i / 100) % 5 == 0 ? 0.0 : 1e-6 * (1.0 + static_cast<double>(i % 17));
    gain[i] = 1e5 * (1.0 + 0.001 * static_cast<double>(i));
  }
  for (std::size_t k = 0; k < field.size(); ++k) {
    field[k] = k % 7 == 0 ? std::nan("") : 0.1 + 0.01 * static_cast<double>(k % 300);
  }
  std::vector<std::vector<double>> outs;
  for (const bool with_field : {false, true}) {
    for (int looks = 1; looks <= 3; ++looks) {
      for (const bool max_detector : {true, false}) {
        std::vector<double> out(n);
        sk::DetectorArgs a;
        a.keys = keys.data();
        a.noise_keys = noise_keys.data();
        a.base = base.data();
        a.gain = gain.data();
        a.field = with_field ? field.data() : nullptr;
        a.out = out.data();
        a.n = n;
        a.looks = looks;
        a.max_detector = max_detector;
        a.thermal_power = 2e-6;
        a.floor_power = 0.3;
        a.seed = 11;
        sk::detect(a);
        outs.push_back(out);
      }
    }
  }
  return outs;
}

// AVX-512 and AVX2 run the same float operations lane for lane (FMA both): identical bits. The
// scalar path (HWY_SCALAR) multiplies and adds separately: each operation rounds once more, a few
// float ulps (2^-24 = 6e-8 each) over the chain of log, square root and sums; the bound 2e-6 of
// the sample's scale (its mean power plus the noise powers) holds with room.
TEST(SensorKernel, SimdPathsAgree) {
  simd::set_target(simd::Target::scalar);
  const auto scalar = all_modes();
  std::vector<std::vector<std::vector<double>>> vector_paths;
  for (const simd::Target t : {simd::Target::avx2, simd::Target::avx512}) {
    if (!simd::supported(t)) continue;
    simd::set_target(t);
    vector_paths.push_back(all_modes());
  }
  simd::set_target(simd::Target::automatic);
  if (vector_paths.size() == 2) {
    EXPECT_EQ(vector_paths[0], vector_paths[1]);
  }
  for (const auto& v : vector_paths) {
    ASSERT_EQ(v.size(), scalar.size());
    double worst = 0.0;
    for (std::size_t m = 0; m < v.size(); ++m) {
      for (std::size_t i = 0; i < v[m].size(); ++i) {
        const double scale = std::max(1.0, std::abs(scalar[m][i]));
        worst = std::max(worst, std::abs(v[m][i] - scalar[m][i]) / scale);
      }
    }
    EXPECT_LT(worst, 2e-6);
    std::printf("largest relative difference to the scalar path: %.3g\n", worst);
  }
}

// The texture is UnitGammaTable(nu) of the documented word (sensor_kernel.hpp), computed here
// from the scalar counter hash; shadows and non-positive means passed through, shapes beyond the
// tables by keyed_gamma; inputs that reach the two exactly inverted tail bins and vectors of
// mixed shapes. The vector paths evaluate the bin's quadratic in float32 from the table's float
// copy: within 1e-6 relative of the double table (a few float roundings, 6e-8 each); AVX-512 and
// AVX2 the same bits; the tail bins and large shapes exactly the scalar rule.
TEST(SensorKernel, TextureIsTheGammaTableOfTheDocumentedWord) {
  const std::size_t n = 40001;
  std::vector<std::uint64_t> keys(n);
  std::vector<double> nu(n), mean(n), expected(n);
  const std::uint64_t seed = 23;
  const counter_hash::Stream ss = sk::speckle_stream(seed);
  std::size_t tails = 0, mixed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = splitmix64(i / 3);
    const double shapes[5] = {0.0, 0.5, 4.0, 20.0, 2000.0};
    nu[i] = shapes[(i / 5 + i / 7) % 5];  // changes inside vectors
    mean[i] = i % 11 == 0 ? 0.0 : (i % 13 == 0 ? -1.0 : 1.0 + 0.001 * static_cast<double>(i));
    if (i % 8 != 0 && nu[i] != nu[i - 1]) ++mixed;
    if (!(mean[i] > 0.0) || !(nu[i] > 0.0)) {
      expected[i] = mean[i];
      continue;
    }
    const std::uint32_t w =
        counter_hash::draw(ss, counter_hash::key_word(ss, keys[i]), sk::kTextureCounter);
    if (nu[i] > UnitGammaTable::kMaxShape) {
      expected[i] = mean[i] * (keyed_gamma(nu[i], seed, keys[i], 1u << 20) / nu[i]);
    } else {
      const std::uint64_t k = w >> 20;
      tails += k == 0 || k == UnitGammaTable::kBins - 1 ? 1 : 0;
      expected[i] = mean[i] * UnitGammaTable::get(nu[i])(
                                  high32_midpoint(static_cast<std::uint64_t>(w) << 32));
    }
  }
  ASSERT_GT(tails, 0u);
  ASSERT_GT(mixed, 100u);
  std::vector<std::vector<double>> outs;
  for (const simd::Target t : simd::supported_targets()) {
    simd::set_target(t);
    std::vector<double> base(n, -7.0);
    sk::TextureArgs a;
    a.keys = keys.data();
    a.nu = nu.data();
    a.mean = mean.data();
    a.base = base.data();
    a.n = n;
    a.seed = seed;
    sk::texture(a);
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_NEAR(base[i], expected[i], 1e-6 * std::abs(expected[i]))
          << i << " " << simd::target_name(t);
    }
    outs.push_back(base);
  }
  if (outs.size() == 3) {
    EXPECT_EQ(outs[1], outs[2]);
  }
  simd::set_target(simd::Target::automatic);
}

// Unit mean, variance 1 / nu over consecutive keys (5 standard errors; the fourth moment of
// Gamma(nu) / nu for the variance's: (3 / nu^2 + 6 / nu^3) - 1 / nu^2).
TEST(SensorKernel, TextureIsUnitMeanGamma) {
  const std::size_t n = 200000;
  for (const double shape : {0.7, 5.0}) {
    std::vector<std::uint64_t> keys(n);
    std::iota(keys.begin(), keys.end(), 1000);
    std::vector<double> nu(n, shape), ones(n, 1.0), t(n);
    sk::TextureArgs a;
    a.keys = keys.data();
    a.nu = nu.data();
    a.mean = ones.data();
    a.base = t.data();
    a.n = n;
    a.seed = 5;
    sk::texture(a);
    const double var = 1.0 / shape, m4 = 3.0 / (shape * shape) + 6.0 / (shape * shape * shape);
    const double nn = static_cast<double>(n);
    EXPECT_NEAR(mean(t), 1.0, 5.0 * std::sqrt(var / nn)) << shape;
    EXPECT_NEAR(central(t, 2), var, 5.0 * std::sqrt((m4 - var * var) / nn)) << shape;
  }
}

// The kernel against the reference sampler (SpeckleSampler::exact: Box-Muller and Marsaglia-Tsang
// per look) through detect_speckle, thermal noise and receiver floor on: 3 looks without
// texture (the reference draws a texture per look, the default one per seabed patch shared by
// the looks: the same only for one look) with both detectors, and one look with texture.
// Two-sample Kolmogorov-Smirnov distance below 0.012 (1.36 sqrt(2 / n) = 0.0061 is the 5 %
// critical value for n = 10^5; 0.012 is beyond 6 sigma) and means within 1 %.
TEST(SensorKernel, DetectorMatchesTheExactSamplerInDistribution) {
  const std::size_t n = 100000;
  std::vector<std::uint64_t> keys(n), noise_keys(n);
  std::iota(keys.begin(), keys.end(), 1);
  std::iota(noise_keys.begin(), noise_keys.end(), 1u << 30);
  const std::vector<double> gain(n, 2.0), textured(n, 5.0), untextured;
  struct Case {
    int looks;
    DetectorMode mode;
    const std::vector<double>* nu;
  };
  for (const Case c :
       {Case{3, DetectorMode::max, &untextured}, Case{3, DetectorMode::mean, &untextured},
        Case{1, DetectorMode::max, &textured}}) {
    SensorModel m;
    m.sub_samples = c.looks;
    m.detector = c.mode;
    m.floor_power = 0.2;
    std::vector<std::vector<double>> out;
    for (const SpeckleSampler sampler : {SpeckleSampler::tables, SpeckleSampler::exact}) {
      SpeckleNoise sn;
      sn.thermal_noise_power = 0.3;
      sn.seed = 17;
      sn.sampler = sampler;
      std::vector<double> io(n, 1.0);
      DetectorScratch scratch;
      detect_speckle(m, sn, keys, noise_keys, *c.nu, gain, nullptr, scratch, io);
      std::sort(io.begin(), io.end());
      out.push_back(io);
    }
    const std::string what = std::to_string(c.looks) + " looks, " +
                             (c.mode == DetectorMode::max ? "max" : "mean") +
                             (c.nu->empty() ? "" : ", texture");
    EXPECT_NEAR(mean(out[0]) / mean(out[1]), 1.0, 0.01) << what;
    // KS distance of the sorted samples: the largest gap of the two empirical CDFs.
    double d = 0.0;
    std::size_t j = 0;
    for (std::size_t i = 0; i < n; ++i) {
      while (j < n && out[1][j] <= out[0][i]) ++j;
      d = std::max(d, std::abs(static_cast<double>(i + 1) - static_cast<double>(j)) /
                          static_cast<double>(n));
    }
    EXPECT_LT(d, 0.012) << what;
    std::printf("%s: KS distance %.4f, mean ratio %.4f\n", what.c_str(), d,
                mean(out[0]) / mean(out[1]));
  }
}

TEST(SensorKernel, QuantiseIsTheScalarRuleOnEveryPath) {
  const std::size_t n = 1027;
  std::vector<double> power(n), gain(n);
  for (std::size_t i = 0; i < n; ++i) {
    power[i] = 0.37 * static_cast<double>(i * i) + 0.25;
    gain[i] = 1.0 + 0.01 * static_cast<double>(i % 13);
  }
  power[10] = std::nan("");
  power[11] = -4.0;
  power[12] = std::numeric_limits<double>::infinity();
  power[13] = 2.25;  // amplitude 1.5: rounds up (half away from zero)
  for (const bool amplitude : {true, false}) {
    for (const bool with_gain : {true, false}) {
      sk::QuantiseArgs q;
      q.power = power.data();
      q.gain = with_gain ? gain.data() : nullptr;
      q.first = 3;
      q.n = n;
      q.amplitude = amplitude;
      q.round = true;
      q.max_value = 300.0;
      // The rule, written out.
      std::vector<float> expected(n, -1.0f);
      std::uint32_t sat = 0, inv = 0;
      for (std::size_t i = q.first; i < n; ++i) {
        double v = power[i] * (with_gain ? gain[i] : 1.0);
        if (amplitude) v = std::sqrt(v);
        if (!std::isfinite(v)) {
          v = 0.0;
          ++inv;
        } else if (v >= q.max_value) {
          v = q.max_value;
          ++sat;
        }
        expected[i] = static_cast<float>(std::round(std::max(v, 0.0)));
      }
      for (const simd::Target t : simd::supported_targets()) {
        simd::set_target(t);
        std::vector<float> out(n, -1.0f);
        std::uint32_t s = 0, iv = 0;
        sk::quantise(q, out.data(), s, iv);
        EXPECT_EQ(out, expected) << simd::target_name(t);
        EXPECT_EQ(s, sat);
        EXPECT_EQ(iv, inv);
      }
      simd::set_target(simd::Target::automatic);
    }
  }
}

}  // namespace
}  // namespace sonarsynth
