// SPDX-License-Identifier: MIT
// The detector of sensor_effects.hpp: the frozen along-track speckle of the lattice, the look
// seeds, and detect_speckle's reference and vector paths (docs/physics.md §1.6).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sonarsynth/along_track_lattice.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/sensor_kernel.hpp"

namespace sonarsynth {
namespace {

// Stream of the receiver noise of look j (distinct from the speckle and thermal streams).
constexpr std::uint64_t kFloorStream = 0x5e15e0f1001ULL;
// Salt of the seeds of look j >= 1.
constexpr std::uint64_t kLookSalt = 0x100000000ULL;

}  // namespace

void AlongTrackTable::prepare(double spacing_m, double beam_rad, std::size_t samples,
                              double array_m) {
  if (spacing_m == sample_spacing_m && beam_rad == beam_3db_rad && array_m == array_length_m &&
      sw.size() == samples) {
    return;
  }
  sample_spacing_m = spacing_m;
  beam_3db_rad = beam_rad;
  array_length_m = array_m;
  sw.resize(samples);
  inv_step.resize(samples);
  sw_max = 0.0;
  const double inv_sqrt_8ln2 = 1.0 / std::sqrt(8.0 * std::log(2.0));
  // Translated aperture (docs/physics.md §1.6): the co-array of a transmitter and a receiver of
  // length D has width D / sqrt(24) (the variance of the mean of two uniform positions).
  const bool aperture = array_m > 0.0 && std::isfinite(array_m);
  const double inv_sc2 = aperture ? 24.0 / (array_m * array_m) : 0.0;
  const double d2 = aperture ? array_m * array_m : 0.0;
  for (std::size_t i = 0; i < samples; ++i) {
    const double r = (static_cast<double>(i) + 0.5) * spacing_m;
    const double far = r * beam_rad * inv_sqrt_8ln2;
    sw[i] = lattice::kWidthFactor *
            (aperture ? 1.0 / std::sqrt(inv_sc2 + 1.0 / (far * far + d2)) : far);
    inv_step[i] = 1.0 / (lattice::kStep * sw[i]);
    sw_max = i == 0 || std::isnan(sw[i]) || sw[i] > sw_max ? sw[i] : sw_max;
  }
}

void along_track_speckle(const AlongTrackField& f, std::size_t samples, int look,
                         std::vector<double>& out) {
  AlongTrackTable table;
  along_track_speckle(f, samples, look, table, out);
}

void along_track_speckle(const AlongTrackField& f, std::size_t samples, int look,
                         AlongTrackTable& table, std::vector<double>& out) {
  along_track_speckle_looks(f, samples, look, 1, table, out);
}

void along_track_speckle_looks(const AlongTrackField& f, std::size_t samples, int first_look,
                               int looks, AlongTrackTable& table, std::vector<double>& out) {
  if (first_look < 0 || looks < 0 || first_look + looks > lattice::kMaxLooks) {
    throw std::invalid_argument("along_track_speckle_looks: looks " + std::to_string(first_look) +
                                " .. " + std::to_string(first_look + looks - 1) +
                                ". Violated constraint: 0 <= look < " +
                                std::to_string(lattice::kMaxLooks));
  }
  const auto nl = static_cast<std::size_t>(looks);
  out.resize(samples * nl);
  lattice::look_sums(f, table, samples, first_look, looks, table.re, table.im, table.norm);
  const std::size_t stride = lattice::padded(samples);
  for (std::size_t j = 0; j < nl; ++j) {
    const float* re = table.re.data() + j * stride;
    const float* im = table.im.data() + j * stride;
    double* o = out.data() + j * samples;
    for (std::size_t i = 0; i < samples; ++i) {
      const auto dre = static_cast<double>(re[i]), dim = static_cast<double>(im[i]);
      // NaN where the lattice does not apply (norm NaN).
      o[i] = (dre * dre + dim * dim) * table.norm[i];
    }
  }
}

namespace {

// Seed of the keyed words of look j: look 0 uses `seed` itself (what apply_speckle_noise
// draws), look j > 0 a seed of its own.
std::uint64_t look_seed(std::uint64_t seed, int j) {
  return j == 0 ? seed : splitmix64(seed ^ (kLookSalt + static_cast<std::uint64_t>(j)));
}

// The reference path (SpeckleSampler::exact): apply_speckle_noise per look with look-keyed keys.
void detect_speckle_exact(const SensorModel& m, const SpeckleNoise& speckle,
                          std::span<const std::uint64_t> keys,
                          std::span<const std::uint64_t> noise_keys,
                          std::span<const double> texture_nu, std::span<const double> out_gain,
                          const AlongTrackField* field, DetectorScratch& s, std::span<double> io) {
  const std::size_t n = io.size();
  const int looks = std::max(1, m.sub_samples);
  const UnitGammaTable& exp1 = UnitGammaTable::get(1.0);
  s.combined.assign(n, 0.0);
  s.sub.resize(n);
  s.keys.resize(n);
  s.noise_keys.resize(n);
  for (int j = 0; j < looks; ++j) {
    std::copy(io.begin(), io.end(), s.sub.begin());
    if (field != nullptr) along_track_speckle(*field, n, j, s.along_track, s.field);
    const std::uint64_t ks = look_seed(0, j);
    for (std::size_t i = 0; i < n; ++i) {
      s.keys[i] = j == 0 ? keys[i] : splitmix_stream(ks, keys[i]);
      s.noise_keys[i] = j == 0 ? noise_keys[i] : splitmix_stream(ks, noise_keys[i]);
    }
    apply_speckle_noise(
        speckle, s.keys, s.noise_keys, texture_nu,
        field != nullptr ? std::span<const double>(s.field) : std::span<const double>{}, s.sub);
    const std::uint64_t fs = look_seed(splitmix64(speckle.seed ^ kFloorStream), j);
    for (std::size_t i = 0; i < n; ++i) {
      double p = s.sub[i] * out_gain[i];
      if (m.floor_power > 0.0) {
        p += m.floor_power * exp1(high32_midpoint(splitmix_stream(fs, noise_keys[i])));
      }
      if (looks == 1) {
        s.combined[i] = p;
      } else if (m.detector == DetectorMode::max) {
        s.combined[i] = std::max(s.combined[i], p);
      } else {
        s.combined[i] += std::sqrt(p);
      }
    }
  }
  if (looks > 1 && m.detector == DetectorMode::mean) {
    const double inv = 1.0 / static_cast<double>(looks);
    for (std::size_t i = 0; i < n; ++i) io[i] = (s.combined[i] * inv) * (s.combined[i] * inv);
  } else {
    std::copy(s.combined.begin(), s.combined.end(), io.begin());
  }
}

// The arguments both vector detectors take (sensor_kernel::DetectorCommon); `s.base` holds the
// textured mean.
void set_detector_common(const SensorModel& m, const SpeckleNoise& speckle,
                         std::span<const std::uint64_t> keys,
                         std::span<const std::uint64_t> noise_keys,
                         std::span<const double> out_gain, int looks, const DetectorScratch& s,
                         std::span<double> io, sensor_kernel::DetectorCommon& a) {
  a.keys = keys.data();
  a.noise_keys = noise_keys.data();
  a.base = s.base.data();
  a.gain = out_gain.data();
  a.out = io.data();
  a.n = io.size();
  a.looks = looks;
  a.max_detector = looks == 1 || m.detector == DetectorMode::max;
  a.thermal_power = speckle.thermal_noise_power;
  a.floor_power = m.floor_power;
  a.seed = speckle.seed;
}

// detect_speckle with the range filter (docs/physics.md §1.6): the vector kernel of
// sensor_kernel.hpp (the frozen complex speckle from the lattice or the speckle words, thermal
// noise, the taps as a FIR in range, the floor and the detector). `s.base` holds the textured
// mean.
void detect_filtered(const SensorModel& m, const SpeckleNoise& speckle,
                     std::span<const std::uint64_t> keys, std::span<const std::uint64_t> noise_keys,
                     std::span<const double> out_gain, const AlongTrackField* field,
                     DetectorScratch& s, std::span<double> io) {
  const std::size_t n = io.size();
  const int looks = std::max(1, m.sub_samples);
  // The lattice's look sums where the textured mean is positive (no speckle work in shadows);
  // none if it applies nowhere.
  AlongTrackTable& at = s.along_track;
  const bool lattice_on = field != nullptr && lattice::look_sums(*field, at, n, 0, looks, at.re,
                                                                 at.im, at.norm, s.base.data()) > 0;
  sensor_kernel::FilteredArgs a;
  set_detector_common(m, speckle, keys, noise_keys, out_gain, looks, s, io, a);
  if (lattice_on) {
    a.field_re = at.re.data();
    a.field_im = at.im.data();
    a.field_norm = at.norm.data();
    a.field_stride = lattice::padded(n);
  }
  a.taps = m.range_taps.data();
  a.taps_n = m.range_taps.size();
  sensor_kernel::detect_filtered(a);
}

}  // namespace

void detect_speckle(const SensorModel& m, const SpeckleNoise& speckle,
                    std::span<const std::uint64_t> keys, std::span<const std::uint64_t> noise_keys,
                    std::span<const double> texture_nu, std::span<const double> out_gain,
                    const AlongTrackField* field, DetectorScratch& s, std::span<double> io) {
  const std::size_t n = io.size();
  check_speckle_inputs(speckle, n, keys, noise_keys, texture_nu, {});
  if (out_gain.size() != n) {
    throw InputError("detect_speckle: out_gain.size() = " + std::to_string(out_gain.size()) +
                     ". Violated constraint: size == io.size() = " + std::to_string(n));
  }
  if (speckle.sampler == SpeckleSampler::exact) {
    detect_speckle_exact(m, speckle, keys, noise_keys, texture_nu, out_gain, field, s, io);
    return;
  }
  // The texture is drawn once for all looks (a vector pass of sensor_kernel.hpp); then the
  // fused vector pass (frozen speckle, thermal and floor noise, gain and detector per block of
  // samples), or the range-filtered one.
  const int looks = std::max(1, m.sub_samples);
  s.base.resize(n);
  sensor_kernel::TextureArgs ta;
  ta.keys = keys.data();
  ta.nu = texture_nu.empty() ? nullptr : texture_nu.data();
  ta.mean = io.data();
  ta.base = s.base.data();
  ta.n = n;
  ta.seed = speckle.seed;
  sensor_kernel::texture(ta);
  if (!m.range_taps.empty()) {
    detect_filtered(m, speckle, keys, noise_keys, out_gain, field, s, io);
    return;
  }
  if (field != nullptr) along_track_speckle_looks(*field, n, 0, looks, s.along_track, s.field);
  sensor_kernel::DetectorArgs a;
  set_detector_common(m, speckle, keys, noise_keys, out_gain, looks, s, io, a);
  a.field = field != nullptr ? s.field.data() : nullptr;
  sensor_kernel::detect(a);
}

double detected_median_of_unit_mean(const SensorModel& m, double nu, std::uint64_t seed) {
  constexpr std::size_t kSamples = 1 << 14;
  std::vector<std::uint64_t> keys(kSamples), noise_keys(kSamples);
  for (std::size_t i = 0; i < kSamples; ++i) {
    keys[i] = splitmix64(0xca11b4a7e0000000ULL + i);
    noise_keys[i] = splitmix64(0xca11b4a7f0000000ULL + i);
  }
  std::vector<double> io(kSamples, 1.0), gain(kSamples, 1.0);
  std::vector<double> texture(nu > 0.0 ? kSamples : 0, nu);
  SensorModel quiet = m;
  quiet.floor_power = 0.0;
  SpeckleNoise sn;
  sn.seed = seed;
  DetectorScratch scratch;
  detect_speckle(quiet, sn, keys, noise_keys, texture, gain, nullptr, scratch, io);
  std::nth_element(io.begin(), io.begin() + kSamples / 2, io.end());
  return io[kSamples / 2];
}

}  // namespace sonarsynth
