// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth {

/// How mosaic_xtf() grids XTF files.
struct XtfMosaicOptions {
  double pixel_size_m = kDefaultMosaicPixelM;  ///< square pixel side, metres, > 0
  MosaicOptions gridding;                      ///< rule, taper...
  /// false (default): SensorX/Ycoordinate is the towfish position (XTF convention, AUVs).
  /// true: it is the tow point; the fish is placed Layback metres behind it along -heading.
  bool apply_layback = false;
  /// Where each ping's altitude comes from (docs/conversion.md): auto (default) = the header's
  /// (SensorPrimaryAltitude) unless it is missing, <= 0 or disagrees with the altitude tracked
  /// from the first return (BottomTracker); header = the header's only (pings without one are
  /// skipped); track = the tracked one only.
  AltitudeSource altitude_source = AltitudeSource::kAuto;
  BottomTrackOptions tracking;
  /// Across-track gain normalisation computed over all the files (docs/conversion.md).
  GainNormalisation gain_normalisation = GainNormalisation::kOff;
  /// Largest mosaic accepted, in pixels (columns x rows), > 0: a larger one is refused with an
  /// InputError naming the extent, the pixel size and this limit, before anything is allocated
  /// (the mean rule holds about 20 bytes per pixel while gridding).
  std::uint64_t max_pixels = std::uint64_t{1} << 28;
  /// A ping whose SlantRange exceeds this many times the median of its file is a navigation
  /// outlier (> 1).
  double max_slant_range_ratio = 10.0;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// The mosaic and what happened to every ping.
struct XtfMosaicResult {
  GeoFrame frame{1, true, 0.0, 0.0};  ///< UTM/UPS zone of the data (or of the bathymetry)
  MosaicImage image;
  std::size_t files = 0;
  std::size_t pings = 0;                   ///< sonar packets read
  std::size_t pings_gridded = 0;           ///< pings that contributed samples
  std::size_t pings_no_navigation = 0;     ///< skipped: zero/invalid/non-geographic position
  std::size_t pings_no_samples = 0;        ///< skipped: no port/starboard channel
  std::size_t pings_no_altitude = 0;       ///< skipped: altitude <= 0 and no bottom pick
  std::size_t pings_tracked_altitude = 0;  ///< gridded with the tracked altitude
  std::size_t pings_header_altitude = 0;   ///< gridded with the header altitude
  std::size_t pings_header_disagreed = 0;  ///< of the tracked: the header's disagreed (auto)
  /// Files left out because no ping has port or starboard samples: one message per file (its
  /// name and ping count).
  std::vector<std::string> skipped_files;
  std::uint64_t samples_placed = 0;
  std::uint64_t fill_points = 0;
  std::uint64_t reader_anomalies = 0;  ///< total over files, reported by xtf::Reader
  /// The first reader anomaly messages (each names its file, packet and value).
  std::vector<std::string> reader_anomaly_messages;
  /// Navigation outliers: pings with samples and a position that were left out of the extent
  /// and of the grid (see mosaic_xtf()).
  std::size_t pings_dropped = 0;
  std::size_t dropped_position_jump = 0;  ///< far from both its predecessors and successors
  std::size_t dropped_slant_range = 0;    ///< SlantRange > max_slant_range_ratio x file median
  std::size_t dropped_heading = 0;        ///< SensorHeading not finite
  /// The first few dropped pings: file, ping number, packet index and the value concerned.
  std::vector<std::string> dropped_examples;
};

/// Mosaics XTF files (any vendor's) into one grid in the UTM/UPS zone of the centroid of their
/// valid sensor positions (with `bathymetry`: its frame, and slant->ground against it).
/// Two passes over the files: navigation and extent, then gridding; one ping in memory at a time.
/// Navigation outliers are dropped (counted in the result, never gridded) before the extent is
/// taken: a non-finite SensorHeading; a SlantRange more than max_slant_range_ratio times the
/// median of its file; a position jump, i.e. a ping farther than max(median slant range,
/// 2 x 5 x median ping spacing) from both the component-wise median of the 5 pings before it
/// and that of the 5 pings after it (one side at the ends of a file), so that a survey
/// resuming elsewhere after a gap is kept while a single bad fix is not. The extent is then
/// checked against max_pixels.
/// Heading: SensorHeading (true, converted to grid azimuth with the meridian convergence);
/// altitude: SensorPrimaryAltitude; pitch: SensorPitch. Intensities are gridded as stored
/// (linear units), never in dB.
/// A file without any port/starboard channel is skipped and named in skipped_files; the
/// altitudes are tracked per file (one more pass), and with gain normalisation its statistics
/// are gathered over all files before gridding (one more pass).
/// Throws FormatError naming the file for unreadable files, naming every file when none has a
/// port/starboard channel, or no ping with valid navigation in any file; InputError for bad
/// options or a mosaic of more than max_pixels.
XtfMosaicResult mosaic_xtf(const std::vector<std::filesystem::path>& files,
                           const XtfMosaicOptions& options = {},
                           const LoadedGrid* bathymetry = nullptr);

/// The tracked altitude (BottomTracker) of every ping of a side-scan file with port or
/// starboard samples, in file order (NaN where none).
std::vector<double> track_file_altitudes(const std::filesystem::path& file,
                                         const BottomTrackOptions& options = {});

}  // namespace sonarsynth
