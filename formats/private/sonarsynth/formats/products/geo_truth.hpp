// SPDX-License-Identifier: MIT
#pragma once
// Private helper of the survey products: the georeferenced truth vectors of a run
// (docs/labels.md, "Target list, track lines and coverage"): targets.geojson (one Point per
// scene object, with the lines and pings that see it), tracks.geojson (one LineString per survey
// line through the sensor positions) and coverage.geojson (per line and side, the ground
// footprint of the swath out to its last seabed sample), WGS 84 longitude/latitude.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/ping_sink.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth::geo_truth {

/// How one object is seen on one line: pings (ping_in_line, as the XTF ping numbers) whose
/// per-sample truth has the object's id on either side.
struct Sighting {
  std::size_t line = 0;
  std::uint64_t first_ping = 0;
  std::uint64_t last_ping = 0;
  std::uint64_t pings = 0;  ///< pings with at least one sample of the object
  UtcTime first_time{};
  UtcTime last_time{};
};

/// A PingSink collecting the vectors while the pings stream through, writing the three files
/// (each atomically) in finish(). Pings without per-sample truth add to the tracks only.
class GeoTruthWriter final : public PingSink {
 public:
  /// `scene` (shared, not null) gives the objects and the frame; `line_names` name the lines.
  GeoTruthWriter(std::filesystem::path dir, std::shared_ptr<const Scene> scene,
                 std::vector<std::string> line_names, bool overwrite);
  ~GeoTruthWriter() override;
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& p) override;
  void end_line(std::size_t line) override;
  void finish() override;
  void abort() noexcept override;

  /// The files written (after finish()).
  const std::vector<std::filesystem::path>& files() const { return files_; }
  /// The sightings of the object with this id, by line (after the pings).
  std::vector<Sighting> sightings(std::int32_t id) const;

 private:
  struct LineData;
  struct Seen {
    std::uint64_t first = 0, last = 0, pings = 0;
    UtcTime first_time{}, last_time{};
  };
  std::filesystem::path dir_;
  std::shared_ptr<const Scene> scene_;
  std::vector<std::string> names_;
  bool overwrite_;
  Eigen::Vector2d centre_xy_m_{0.0, 0.0};  ///< the bathymetry grid's centre (scene east/north 0)
  std::vector<std::int32_t> ids_;          ///< sorted object ids
  /// [object index][line]: pings that saw it (pings == 0: none).
  std::vector<std::vector<Seen>> seen_;
  std::vector<std::unique_ptr<LineData>> lines_;
  std::vector<std::uint8_t> marked_;  ///< scratch: objects seen in the current ping
  std::vector<std::filesystem::path> files_;
};

}  // namespace sonarsynth::geo_truth
