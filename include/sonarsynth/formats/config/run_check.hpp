// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

/// Which products `simulate` will write besides the XTF files (for the size estimates).
struct ProductPlan {
  bool mosaic = true;
  bool waterfalls = true;
  bool truth = true;
  double mosaic_pixel_m = kDefaultMosaicPixelM;
};

/// What the check found about one survey line, from poses sampled evenly along it.
struct LineCheck {
  std::string name;
  std::uint64_t pings = 0;
  std::size_t sampled = 0;            ///< poses examined
  double seabed_fraction = 0.0;       ///< of the sampled poses, those over valid seabed
  double short_range_fraction = 0.0;  ///< of those over seabed, range_m <= altitude
};

/// The whole run, estimated before rendering.
struct RunPlan {
  std::vector<LineCheck> lines;
  std::uint64_t total_pings = 0;
  std::uint64_t output_bytes = 0;  ///< XTF files + products, uncompressed upper bound
  std::uint64_t memory_bytes = 0;  ///< renderer workspaces + mosaic accumulators
  std::vector<std::string> warnings;
};

/// Checks a run before anything is rendered or written (format: docs/scene-format.md, section
/// "Checks before the run"): every line's coverage of valid seabed, the sensor between the
/// seabed and the surface, range longer than the altitude, and the total pings, output bytes and
/// memory against setup.limits and the free space at `out_dir`. Throws InputError naming the
/// file, the line or key and the value for a fatal problem; returns the estimates and warnings.
RunPlan check_simulation(const std::string& scene_path, const SimulationSetup& setup,
                         const ProductPlan& products, const std::filesystem::path& out_dir);

/// Counts, per line, the samples clamped at the top of the sample range, the non-finite samples
/// written as 0 and the pings with no seabed under the sensor, as the simulator produced them.
class RunStatistics : public PingSink {
 public:
  struct Line {
    std::uint64_t pings = 0;
    std::uint64_t samples = 0;
    std::uint64_t saturated = 0;
    std::uint64_t invalid = 0;
    std::uint64_t no_seabed_pings = 0;
  };
  explicit RunStatistics(std::size_t lines = 0) : lines_(lines) {}
  /// Starts counting afresh for run.line_count lines.
  void begin(const RunDescription& run) override {
    lines_.assign(run.line_count, Line{});
    current_ = 0;
  }
  void begin_line(std::size_t line) override { current_ = line; }
  void ping(const RenderedPing& ping) override;
  const std::vector<Line>& lines() const { return lines_; }

  /// One warning per line with more than `max_fraction` of its samples saturated or invalid,
  /// and per line with pings over no seabed; `max_value` and `gain_db` are named in them
  /// (gain_db NaN: the run was normalised per ping, OutputScaling::Normalise::per_ping_max).
  std::vector<std::string> warnings(const std::vector<std::string>& names, double max_value,
                                    double gain_db, double max_fraction = 0.02) const;

 private:
  std::vector<Line> lines_;
  std::size_t current_ = 0;
};

}  // namespace sonarsynth
