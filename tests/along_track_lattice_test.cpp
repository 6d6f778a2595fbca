// SPDX-License-Identifier: MIT
// The along-track speckle lattice's kernel (lib/along_track_lattice.cpp, docs/physics.md §1.6):
// every SIMD path against a reference computed here in double with std:: maths; the scatterers'
// unit power; the along-track correlation of the three-scatterer lattice against its closed
// form.
#include "sonarsynth/along_track_lattice.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sonarsynth/counter_hash.hpp"
#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/simd.hpp"

namespace {

using namespace sonarsynth;
namespace simd = sonarsynth::simd;

// The far-field lattice width of sample i (array_length_m = 0): r theta / sqrt(8 ln 2), times
// the three-scatterer lattice's width factor.
double far_width(const AlongTrackField& f, std::size_t i) {
  return lattice::kWidthFactor * (static_cast<double>(i) + 0.5) * f.sample_spacing_m *
         f.beam_3db_rad / std::sqrt(8.0 * std::log(2.0));
}

// Look `look` of sample i as the kernel's definition reads (docs/physics.md §1.6), in double:
// the three lattice points nearest u = s / (1.5 sw), weights exp(-(x_m - s)^2 / (2 sw^2)),
// scatterers from the keyed words, normalised by the sum of the squared weights.
bool reference_field(const AlongTrackField& f, std::size_t i, std::uint32_t look, double& re,
                     double& im) {
  const double sw = far_width(f, i);
  const double u = f.along_track_m / (1.5 * sw);
  if (i < f.first_sample || f.ping_spacing_m > 4.43 * sw) return false;
  const double m0 = std::floor(u);
  const auto first = static_cast<std::int64_t>(u - m0 < 0.5 ? m0 - 1.0 : m0);
  const counter_hash::Stream s = lattice::line_stream(lattice::line_word(f));
  re = 0.0;
  im = 0.0;
  double w2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t m = first + k;
    const double x = 1.5 * sw * static_cast<double>(m) - f.along_track_m;
    const double w = std::exp(-x * x / (2.0 * sw * sw));
    const std::uint32_t h = counter_hash::key_word(s, lattice::key_lo(m), lattice::key_hi(i, m));
    double zr, zi;
    lattice::scatterer_reference(counter_hash::draw(s, h, look), zr, zi);
    re += w * zr;
    im += w * zi;
    w2 += w * w;
  }
  re /= std::sqrt(w2);
  im /= std::sqrt(w2);
  return true;
}

AlongTrackField test_field(double along_track_m) {
  AlongTrackField f;
  f.key = 11;
  f.seed = 2024;
  f.sample_spacing_m = 0.02;
  f.beam_3db_rad = 0.01;
  f.first_sample = 40;
  f.ping_spacing_m = 0.05;
  f.along_track_m = along_track_m;
  return f;
}

// The complex field of every look and sample on the active target: re, im (NaN where the
// lattice does not apply).
void kernel_field(const AlongTrackField& f, std::size_t samples, int looks, std::vector<double>& re,
                  std::vector<double>& im) {
  AlongTrackTable table;
  lattice::look_sums(f, table, samples, 0, looks, table.re, table.im, table.norm);
  const std::size_t stride = lattice::padded(samples);
  re.assign(samples * static_cast<std::size_t>(looks), 0.0);
  im.assign(re.size(), 0.0);
  for (std::size_t j = 0; j < static_cast<std::size_t>(looks); ++j) {
    for (std::size_t i = 0; i < samples; ++i) {
      const double g = std::sqrt(table.norm[i]);
      re[j * samples + i] = static_cast<double>(table.re[j * stride + i]) * g;
      im[j * samples + i] = static_cast<double>(table.im[j * stride + i]) * g;
    }
  }
}

// Every SIMD path the CPU runs equals the double reference within 3e-6 per component (float
// sums of three terms, polynomial log, sin and cos: measured up to 6.4e-7), plus 5e-15 |u| (the
// ping's position u in lattice steps, rounded in double differently here: up to 1.1e-5 at
// u ~ 2^32), where the lattice applies and only there; AVX2 and AVX-512 give the same bits. The
// ping positions put the lattice index across 0 (negative keys) and across 2^32 (the carry into the
// key's high half).
TEST(AlongTrackLattice, EverySimdPathMatchesTheReference) {
  const std::size_t samples = 1500;  // not a multiple of the block: a partial last block
  const int looks = 3;
  const double sw_last = far_width(test_field(0.0), samples - 1);
  const double u_wrap = 4294967296.0;  // 2^32 lattice steps at the last sample
  for (const double s_m : {0.0, -3.7, 1234.56, 1.5 * sw_last * u_wrap - 0.004}) {
    const AlongTrackField f = test_field(s_m);
    std::vector<double> avx2_re, avx2_im;
    for (const simd::Target t : simd::supported_targets()) {
      simd::set_target(t);
      std::vector<double> re, im;
      kernel_field(f, samples, looks, re, im);
      double worst = 0.0;
      std::size_t applied = 0;
      for (std::size_t j = 0; j < static_cast<std::size_t>(looks); ++j) {
        for (std::size_t i = 0; i < samples; ++i) {
          double rr, ri;
          const bool have = reference_field(f, i, static_cast<std::uint32_t>(j), rr, ri);
          const std::size_t at = j * samples + i;
          ASSERT_EQ(have, !std::isnan(re[at]))
              << simd::target_name(t) << " s " << s_m << " i " << i;
          if (!have) continue;
          ++applied;
          // The position in lattice steps, rounded differently in double here and in the table.
          const double u = std::abs(s_m) / (1.5 * far_width(f, i));
          worst = std::max(
              {worst, std::abs(re[at] - rr) - 5e-15 * u, std::abs(im[at] - ri) - 5e-15 * u});
        }
      }
      EXPECT_GT(applied, samples) << s_m;
      EXPECT_LT(worst, 3e-6) << simd::target_name(t) << " s " << s_m;
      if (t == simd::Target::avx2) {
        avx2_re = re;
        avx2_im = im;
      } else if (t == simd::Target::avx512 && !avx2_re.empty()) {
        for (std::size_t a = 0; a < re.size(); ++a) {
          if (std::isnan(re[a])) continue;
          ASSERT_EQ(re[a], avx2_re[a]) << a;
          ASSERT_EQ(im[a], avx2_im[a]) << a;
        }
      }
    }
    simd::set_target(simd::Target::automatic);
  }
}

// The scatterers' magnitude: -ln of the midpoints of 2^20 equal cells has the mean the kernel
// and the reference divide by (summed here cell by cell), so |z|^2 has mean 1.
TEST(AlongTrackLattice, ScattererPowerHasUnitMean) {
  const double n = 0x1p20;
  double sum = 0.0;
  for (std::uint32_t k = 0; k < (1U << 20); ++k) {
    sum -= std::log((static_cast<double>(k) + 0.5) / n);
  }
  EXPECT_NEAR(lattice::mean_neg_log_midpoints(), sum / n, 1e-12);
  EXPECT_NEAR(sum / n, 1.0, 4e-7);
}

// Intensity correlation of pings d apart (one look, many samples and ping pairs) against the
// closed form of the three-scatterer lattice, |sum_m w_m w'_m|^2 / (sum w^2 sum w'^2) averaged
// over the ping's offset u in the lattice (computed here), within 4 standard errors; and that
// form, with the weights kWidthFactor wider than the footprint's sw, within 0.006 of the
// continuous one exp(-d^2 / (2 sw^2)) (0.021 below it at d = 1.5 sw without the factor: the
// dropped scatterer carries at most 0.55 % of the weight power).
TEST(AlongTrackLattice, CorrelationAlongTrackMatchesTheThreeScattererForm) {
  const auto three = [](double u) {
    const double m0 = std::floor(u);
    return static_cast<std::int64_t>(u - m0 < 0.5 ? m0 - 1.0 : m0);
  };
  const auto form = [&](double d_steps) {
    double sum = 0.0;
    const int n = 2000;
    for (int q = 0; q < n; ++q) {
      const double u = (q + 0.5) / n, v = u + d_steps;
      const std::int64_t a = three(u), b = three(v);
      double num = 0.0, wa2 = 0.0, wb2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double wa = std::exp(-1.125 * std::pow(static_cast<double>(a + k) - u, 2));
        const double wb = std::exp(-1.125 * std::pow(static_cast<double>(b + k) - v, 2));
        wa2 += wa * wa;
        wb2 += wb * wb;
        for (int kk = 0; kk < 3; ++kk) {
          if (a + k == b + kk) {
            num += wa * std::exp(-1.125 * std::pow(static_cast<double>(a + k) - v, 2));
          }
        }
      }
      sum += num * num / (wa2 * wb2);
    }
    return sum / n;
  };
  // A band of samples where sw varies by +-9 %: pings d = d_sw sw(band centre) apart (the closed
  // form averaged over the band's d / sw).
  const std::size_t i0 = 3000, i1 = 3600;
  AlongTrackField f = test_field(0.0);
  f.first_sample = 0;
  f.ping_spacing_m = 0.0;
  const double sw_mid = far_width(f, (i0 + i1) / 2);
  AlongTrackTable table;
  std::vector<double> a, b;
  for (const double d_sw : {0.5, 1.0, 2.0}) {
    double expected = 0.0;
    for (std::size_t i = i0; i < i1; ++i) expected += form(d_sw * sw_mid / (1.5 * far_width(f, i)));
    expected /= static_cast<double>(i1 - i0);
    double c = 0.0;
    std::size_t n = 0;
    for (int pair = 0; pair < 800; ++pair) {
      f.along_track_m = 50.0 * pair;
      along_track_speckle_looks(f, i1, 0, 1, table, a);
      AlongTrackField g = f;
      g.along_track_m += d_sw * sw_mid;
      along_track_speckle_looks(g, i1, 0, 1, table, b);
      for (std::size_t i = i0; i < i1; ++i) {
        c += (a[i] - 1.0) * (b[i] - 1.0);
        ++n;
      }
    }
    const double measured = c / static_cast<double>(n);
    // Var((S - 1)(S' - 1)) for unit exponentials lies between 1 (independent) and 8 (equal:
    // E (S - 1)^4 - 1); the samples and the pairs are independent.
    const double se = std::sqrt(8.0 / static_cast<double>(n));
    EXPECT_NEAR(measured, expected, 4.0 * se) << d_sw;
  }
  for (const double d_sw : {0.5, 1.0, 1.5, 2.0, 3.0}) {  // d in units of the footprint's sw
    const double continuous = std::exp(-0.5 * d_sw * d_sw);
    EXPECT_NEAR(form(d_sw / (1.5 * lattice::kWidthFactor)), continuous, 0.006) << d_sw;
  }
  // Without the factor, 0.021 below at d = 1.5 sw.
  EXPECT_LT(form(1.0), std::exp(-0.5 * 1.5 * 1.5) - 0.018) << "the factor is needed";
}

// Where the lattice applies: nowhere when the pings are more than 2.5 footprints apart at every
// range (no kernel work, all NaN), and only where `need` is positive when given (elsewhere NaN,
// the other samples unchanged).
TEST(AlongTrackLattice, AppliesOnlyWherePingsOverlapAndWhereNeeded) {
  const std::size_t samples = 700;
  AlongTrackField f = test_field(12.5);
  AlongTrackTable table;
  const std::size_t all =
      lattice::look_sums(f, table, samples, 0, 2, table.re, table.im, table.norm);
  const std::vector<double> norm_all(table.norm.begin(), table.norm.end());
  const std::vector<float> re_all(table.re.begin(), table.re.end());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < samples; ++i) finite += std::isnan(norm_all[i]) ? 0 : 1;
  EXPECT_EQ(all, finite);
  EXPECT_GT(all, samples / 2);
  std::vector<double> need(samples);
  for (std::size_t i = 0; i < samples; ++i) need[i] = i % 3 == 0 ? 0.0 : 1.0;
  const std::size_t needed =
      lattice::look_sums(f, table, samples, 0, 2, table.re, table.im, table.norm, need.data());
  std::size_t expected = 0;
  for (std::size_t i = 0; i < samples; ++i) {
    if (need[i] > 0.0 && !std::isnan(norm_all[i])) {
      ++expected;
      EXPECT_EQ(table.norm[i], norm_all[i]) << i;
      EXPECT_EQ(table.re[i], re_all[i]) << i;
    } else {
      EXPECT_TRUE(std::isnan(table.norm[i])) << i;
    }
  }
  EXPECT_EQ(needed, expected);
  // The largest footprint at 700 samples: sw = 14 m 0.01 / sqrt(8 ln 2) = 0.059 m.
  f.ping_spacing_m = 4.43 * far_width(f, samples - 1) * 1.01;
  EXPECT_EQ(lattice::look_sums(f, table, samples, 0, 2, table.re, table.im, table.norm), 0U);
  for (std::size_t i = 0; i < samples; ++i) EXPECT_TRUE(std::isnan(table.norm[i])) << i;
}

}  // namespace
