// SPDX-License-Identifier: MIT
// The ROS-free part of sonarsynth_ros (docs/robotics.md, "The live ROS 1 node").
#include "node_core.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/option_table.hpp"

namespace sonarsynth::ros_node {

Attitude attitude_of(const Eigen::Quaterniond& q_in) {
  const Eigen::Quaterniond q = q_in.normalized();
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  const double roll = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return {std::numbers::pi / 2 - yaw, -pitch, roll};
}

OdomSample interpolate(const OdomSample& a, const OdomSample& b, std::uint64_t t_ns) {
  if (t_ns <= a.stamp_ns || b.stamp_ns <= a.stamp_ns) return a;
  if (t_ns >= b.stamp_ns) return b;
  const double f =
      static_cast<double>(t_ns - a.stamp_ns) / static_cast<double>(b.stamp_ns - a.stamp_ns);
  OdomSample s;
  s.stamp_ns = t_ns;
  s.position_m = a.position_m + f * (b.position_m - a.position_m);
  s.orientation = a.orientation.normalized().slerp(f, b.orientation.normalized());
  s.speed_m_s = a.speed_m_s + f * (b.speed_m_s - a.speed_m_s);
  return s;
}

PingPose ping_pose(const OdomSample& s, std::uint64_t ping_index, const HeightGrid& seabed) {
  const Attitude att = attitude_of(s.orientation);
  PingPose p =
      sensor_pose(s.position_m, att.heading_rad, att.pitch_rad, att.roll_rad, seabed, ping_index);
  p.ping_in_line = ping_index;
  p.time_utc = UtcTime(std::chrono::microseconds(s.stamp_ns / 1000u));
  p.speed_m_s = s.speed_m_s;
  return p;
}

PingClock::PingClock(double period_s, double max_gap_s)
    : period_ns_(period_s * 1e9), max_gap_ns_(0) {
  if (!(period_s > 0.0) || !std::isfinite(period_s)) {
    throw InputError("sonarsynth_ros: ping period = " + std::to_string(period_s) +
                     " s. Violated constraint: > 0");
  }
  if (!(max_gap_s > 0.0) || !(max_gap_s < 1e9)) {
    throw InputError("sonarsynth_ros: ~max_pose_gap_s = " + std::to_string(max_gap_s) +
                     ". Violated constraint: > 0 and < 1e9 s");
  }
  max_gap_ns_ = static_cast<std::uint64_t>(std::llround(max_gap_s * 1e9));
}

std::uint64_t PingClock::ping_time_ns(std::uint64_t index) const {
  return t0_ns_ + static_cast<std::uint64_t>(std::llround(static_cast<double>(index) * period_ns_));
}

bool PingClock::add(const OdomSample& s, std::vector<ScheduledPing>& due) {
  if (!started_) {
    started_ = true;
    t0_ns_ = s.stamp_ns;
    last_ = s;
    due.push_back({0, s.stamp_ns, s});
    next_ = 1;
    return true;
  }
  if (s.stamp_ns <= last_.stamp_ns) return false;
  const bool gap = s.stamp_ns - last_.stamp_ns > max_gap_ns_;
  for (std::uint64_t t = ping_time_ns(next_); t <= s.stamp_ns; t = ping_time_ns(++next_)) {
    if (gap) {
      ++skipped_;
    } else {
      due.push_back({next_, t, interpolate(last_, s, t)});
    }
  }
  last_ = s;
  return true;
}

std::vector<std::string> option_paths() {
  std::vector<std::string> out;
  for (const options::Option& o : options::all()) out.push_back(o.path());
  return out;
}

SimulationSetup load_setup(const std::string& path, const OptionValues& values,
                           const SimulationOverrides& overrides) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError("sonarsynth_ros: ~scene = " + path + ": " + e.what());
  }
  const std::vector<std::string> known = option_paths();
  for (const auto& [key, text] : values) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw InputError("sonarsynth_ros: '" + key +
                       "' is not an option of a scene file (docs/scene-format.md)");
    }
    // Walk the key path, creating its maps (YAML::Node assignment rebinds, hence the list).
    std::vector<YAML::Node> chain{root};
    std::size_t start = 0;
    for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
      chain.push_back(chain.back()[key.substr(start, dot - start)]);
      start = dot + 1;
    }
    chain.back()[key.substr(start)] = YAML::Load(text);
  }
  const std::filesystem::path p(path);
  try {
    return load_simulation_from_string(YAML::Dump(root), path, p.parent_path(), overrides);
  } catch (const InputError& e) {
    if (values.empty()) throw;
    std::string given;  // the parameters written into the file, for a message naming a key
    for (const auto& [key, text] : values) given += (given.empty() ? "" : ", ") + key + "=" + text;
    throw InputError(std::string(e.what()) + " (node parameters applied to the file: " + given +
                     ")");
  }
}

std::shared_ptr<const Simulator> make_simulator(SimulationSetup& setup) {
  std::vector<PingPose> pilot;
  if (!setup.lines.empty()) pilot = pilot_poses(setup.make_survey(), setup.scene.bathymetry);
  auto scene = std::make_shared<const Scene>(std::move(setup.scene));
  return std::make_shared<const Simulator>(scene, setup.config, setup.reference_altitude_m, pilot);
}

Waterfall::Waterfall(std::size_t rows, std::size_t samples, Colormap map, double full_scale)
    : rows_(rows), samples_(samples), map_(map), full_scale_(full_scale) {
  if (rows < 1 || samples < 1) {
    throw InputError("sonarsynth_ros: ~waterfall/rows = " + std::to_string(rows) +
                     ". Violated constraint: >= 1");
  }
  ring_.assign(rows_ * width() * 3, 0);
}

void Waterfall::add(const RenderedPing& ping) {
  head_ = (head_ + rows_ - 1) % rows_;
  filled_ = std::min(filled_ + 1, rows_);
  std::uint8_t* row = ring_.data() + head_ * width() * 3;
  const auto put = [&](std::size_t col, float v) {
    const Rgb8 c = colormap(map_, static_cast<double>(v) / full_scale_);
    row[3 * col] = c.r;
    row[3 * col + 1] = c.g;
    row[3 * col + 2] = c.b;
  };
  const auto& port = ping.port.samples;
  const auto& stbd = ping.starboard.samples;
  for (std::size_t i = 0; i < samples_; ++i) {
    put(samples_ - 1 - i, i < port.size() ? port[i] : 0.0f);
    put(samples_ + i, i < stbd.size() ? stbd[i] : 0.0f);
  }
}

void Waterfall::image(std::uint8_t* rgb) const {
  const std::size_t row_bytes = width() * 3;
  std::fill(rgb, rgb + rows_ * row_bytes, std::uint8_t{0});
  for (std::size_t r = 0; r < filled_; ++r) {
    const std::uint8_t* src = ring_.data() + ((head_ + r) % rows_) * row_bytes;
    std::copy(src, src + row_bytes, rgb + r * row_bytes);
  }
}

const double LatencyHistogram::kRelativeError = std::exp2(0.5 / kBinsPerOctave) - 1.0;

void LatencyHistogram::add(double latency_s) {
  const double v = latency_s > 0.0 ? latency_s : 0.0;  // also NaN -> 0
  std::size_t bin = 0;
  if (v >= kHighestS) {
    bin = kBins - 1;
  } else if (v >= kLowestS) {
    const double octaves = std::log2(v / kLowestS);
    bin = 1 + std::min(static_cast<std::size_t>(octaves * kBinsPerOctave), kBins - 3);
  }
  ++counts_[bin];
  min_ = count_ == 0 ? v : std::min(min_, v);
  max_ = count_ == 0 ? v : std::max(max_, v);
  ++count_;
}

double LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const double rank_d = std::ceil(q * static_cast<double>(count_));
  const std::uint64_t rank =
      rank_d < 1.0 ? 1 : std::min(count_, static_cast<std::uint64_t>(rank_d));
  std::uint64_t seen = 0;
  std::size_t bin = 0;
  for (; bin < kBins; ++bin) {
    seen += counts_[bin];
    if (seen >= rank) break;
  }
  if (bin == 0) return min_;  // the value is in [min, kLowestS)
  if (bin == kBins - 1) return max_;
  const double centre = kLowestS * std::exp2((static_cast<double>(bin - 1) + 0.5) / kBinsPerOctave);
  return std::clamp(centre, min_, max_);
}

void LatencyHistogram::clear() {
  *this = LatencyHistogram{};
}

}  // namespace sonarsynth::ros_node
