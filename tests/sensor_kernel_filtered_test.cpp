// SPDX-License-Identifier: MIT
// The range-filtered detector's vector kernel (sensor_kernel::detect_filtered,
// lib/sensor_kernel.cpp, docs/physics.md §1.6) against a double-precision reference of the
// documented filter and words.
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
#include "sonarsynth/sensor_kernel.hpp"
#include "sonarsynth/simd.hpp"

namespace sonarsynth {
namespace {

namespace sk = sensor_kernel;
constexpr double kPi = 3.14159265358979323846;

// The range-filtered detector against this file's own double-precision evaluation of its
// documented words and formula (sensor_kernel.hpp): z per sample and look, the FIR with the
// taps inside the record renormalised, |y|^2 gain plus the floor, the looks' detector. Every
// branch: shadows and bad means, a lattice field with gaps, thermal noise and floor, 1-3 looks,
// both detectors, a CW and a chirp filter, a length that is no multiple of a block. Float32 with
// fused operations against double: within 2e-5 of the sample's power scale (the terms' sizes
// before the filter's cancellations). AVX-512 and AVX2 give the same bits.
struct FilteredCase {
  std::size_t n = 1500;
  std::vector<std::uint64_t> keys, noise_keys;
  std::vector<double> base, gain, norm, taps;
  std::vector<float> re, im;
  std::size_t stride = 0;
  FilteredCase(const std::vector<double>& t, int looks) : taps(t) {
    keys.resize(n);
    noise_keys.resize(n);
    base.resize(n);
    gain.resize(n);
    norm.resize(n);
    stride = n + 7;
    re.resize(stride * static_cast<std::size_t>(looks));
    im.resize(re.size());
    for (std::size_t i = 0; i < n; ++i) {
      keys[i] = splitmix64(i / 3);
      noise_keys[i] = splitmix64(i + 0x2000000);
      const std::size_t band = (i / 90) % 6;
      base[i] = band == 0 ? 0.0 : band == 1 && i % 5 == 0 ? -1.0 : 1e-7 * (1.0 + double(i % 19));
      gain[i] = 1e6 * (1.0 + 0.002 * static_cast<double>(i));
      norm[i] = i % 9 == 0 ? std::nan("") : 0.5 + 0.001 * static_cast<double>(i % 100);
    }
    for (std::size_t k = 0; k < re.size(); ++k) {
      re[k] = k % 13 == 0 ? std::nanf("") : 0.3f + 0.01f * static_cast<float>(k % 50);
      im[k] = -0.2f + 0.005f * static_cast<float>(k % 70);
    }
  }
};

std::vector<double> run_filtered(const FilteredCase& c, bool lattice, int looks, bool max_det,
                                 double thermal, double floor) {
  std::vector<double> out(c.n);
  sk::FilteredArgs a;
  a.keys = c.keys.data();
  a.noise_keys = c.noise_keys.data();
  a.base = c.base.data();
  a.gain = c.gain.data();
  if (lattice) {
    a.field_re = c.re.data();
    a.field_im = c.im.data();
    a.field_norm = c.norm.data();
    a.field_stride = c.stride;
  }
  a.taps = c.taps.data();
  a.taps_n = c.taps.size();
  a.out = out.data();
  a.n = c.n;
  a.looks = looks;
  a.max_detector = max_det;
  a.thermal_power = thermal;
  a.floor_power = floor;
  a.seed = 31;
  sk::detect_filtered(a);
  return out;
}

// The reference, and per sample the power scale of its terms.
void reference_filtered(const FilteredCase& c, bool lattice, int looks, bool max_det,
                        double thermal, double floor, std::vector<double>& ref,
                        std::vector<double>& scale) {
  const std::size_t n = c.n, nt = c.taps.size(), K = nt / 2;
  const counter_hash::Stream ss = sk::speckle_stream(31), sn = sk::noise_stream(31);
  const auto exp1 = [](std::uint32_t w) {
    return -std::log(static_cast<double>(counter_hash::uniform_open(w)));
  };
  const auto phase = [](std::uint32_t w, double& cr, double& ci) {
    const double th = static_cast<double>(counter_hash::uniform_open(w)) * kPi / 2.0;
    cr = (w & 1u) != 0 ? -std::cos(th) : std::cos(th);
    ci = (w & 2u) != 0 ? -std::sin(th) : std::sin(th);
  };
  ref.assign(n, 0.0);
  scale.assign(n, 0.0);
  std::vector<double> zr(n), zi(n), mag(n);
  for (int j = 0; j < looks; ++j) {
    const auto ju = static_cast<std::uint32_t>(j);
    for (std::size_t t = 0; t < n; ++t) {
      double r = 0.0, i = 0.0;
      const double b = c.base[t];
      mag[t] = 0.0;
      if (b > 0.0) {
        const std::size_t fk = static_cast<std::size_t>(j) * c.stride + t;
        const double fa = std::sqrt(c.norm[t] * b);
        if (lattice && !std::isnan(c.re[fk] * fa)) {
          r = c.re[fk] * fa;
          i = c.im[fk] * fa;
        } else {
          const std::uint32_t h = counter_hash::key_word(ss, c.keys[t]);
          const double e = exp1(counter_hash::draw(ss, h, ju));
          double cr, ci;
          phase(counter_hash::draw(ss, h, sk::kPhaseCounter + ju), cr, ci);
          r = std::sqrt(e * b) * cr;
          i = std::sqrt(e * b) * ci;
        }
        mag[t] = r * r + i * i;
      }
      if (thermal > 0.0) {
        const std::uint32_t h = counter_hash::key_word(sn, c.noise_keys[t]);
        const double e = exp1(counter_hash::draw(sn, h, 3 * ju));
        double cr, ci;
        phase(counter_hash::draw(sn, h, 3 * ju + 1), cr, ci);
        r += std::sqrt(e * thermal) * cr;
        i += std::sqrt(e * thermal) * ci;
        mag[t] += e * thermal;
      }
      zr[t] = r;
      zi[t] = i;
    }
    for (std::size_t o = 0; o < n; ++o) {
      double yr = 0.0, yi = 0.0, w2 = 0.0, sum_h = 0.0, top = 0.0;
      for (std::size_t k = 0; k < nt; ++k) {
        if (o + k < K || o + k - K >= n) continue;
        const std::size_t t = o + k - K;
        yr += c.taps[k] * zr[t];
        yi += c.taps[k] * zi[t];
        w2 += c.taps[k] * c.taps[k];
        sum_h += std::abs(c.taps[k]);
        top = std::max(top, mag[t]);
      }
      double p = (yr * yr + yi * yi) * c.gain[o] / w2;
      double sc = sum_h * sum_h * top * c.gain[o] / w2;
      if (floor > 0.0) {
        const std::uint32_t h = counter_hash::key_word(sn, c.noise_keys[o]);
        const double e = floor * exp1(counter_hash::draw(sn, h, 3 * ju + 2));
        p += e;
        sc += e;
      }
      scale[o] = std::max(scale[o], sc);
      if (j == 0) {
        ref[o] = max_det ? p : std::sqrt(p);
      } else if (max_det) {
        ref[o] = std::max(ref[o], p);
      } else {
        ref[o] += std::sqrt(p);
      }
    }
  }
  if (!max_det) {
    for (double& v : ref) v = (v / looks) * (v / looks);
  }
}

TEST(SensorKernel, FilteredDetectorIsTheDocumentedFilterOfTheDocumentedWords) {
  SonarConfig cw;
  cw.max_range_m = 30.0;
  cw.samples_per_channel = 600;  // 5 cm samples
  cw.pulse = SonarConfig::Pulse::kCw;
  cw.pulse_length_s = 2.0 * 0.12 / cw.sound_speed_m_s;  // W = 12 cm
  SonarConfig chirp = cw;
  chirp.pulse = SonarConfig::Pulse::kChirp;
  chirp.bandwidth_hz = cw.sound_speed_m_s / (2.0 * 0.1);  // W = 10 cm, taps to 30 cm
  double worst = 0.0;
  for (const SonarConfig& sonar : {cw, chirp}) {
    const std::vector<double> taps = range_filter_taps(sonar);
    ASSERT_GE(taps.size(), 5u);
    for (int looks = 1; looks <= 3; ++looks) {
      const FilteredCase c(taps, looks);
      for (const bool lattice : {false, true}) {
        for (const bool max_det : {true, false}) {
          const double thermal = looks == 2 ? 0.0 : 3e-7, floor = looks == 3 ? 0.0 : 0.4;
          std::vector<double> ref, scale;
          reference_filtered(c, lattice, looks, max_det, thermal, floor, ref, scale);
          std::vector<std::vector<double>> outs;
          for (const simd::Target t : simd::supported_targets()) {
            simd::set_target(t);
            outs.push_back(run_filtered(c, lattice, looks, max_det, thermal, floor));
            for (std::size_t i = 0; i < c.n; ++i) {
              const double err = std::abs(outs.back()[i] - ref[i]) / scale[i];
              worst = std::max(worst, err);
              ASSERT_LT(err, 2e-5) << simd::target_name(t) << " sample " << i << " looks " << looks
                                   << " lattice " << lattice;
            }
          }
          simd::set_target(simd::Target::automatic);
          // supported_targets(): scalar, AVX2, AVX-512 where they run.
          if (outs.size() == 3) {
            EXPECT_EQ(outs[1], outs[2]);
          }
        }
      }
    }
  }
  std::printf("largest difference to the double reference, of the power scale: %.3g\n", worst);
}

}  // namespace
}  // namespace sonarsynth
