// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/colormap.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth {

namespace detail {
class SideSpool;

/// What the waterfall products (Waterfall, TruthWaterfall, LabelWaterfall) share: the spool file
/// their rows go to (formats/products/row_spool.cpp), which the product creates.
class SpooledRows {
 public:
  /// Pings added so far.
  std::size_t rows() const;
  /// 2 x the longest side added so far.
  std::size_t cols() const;

 protected:
  SpooledRows();
  explicit SpooledRows(std::unique_ptr<SideSpool> spool);
  ~SpooledRows();
  SpooledRows(SpooledRows&&) noexcept;
  SpooledRows& operator=(SpooledRows&&) noexcept;

  std::unique_ptr<SideSpool> spool_;
};
}  // namespace detail

/// How a waterfall image is scaled and written.
/// libpng's default limit on an image's width (PNG_USER_WIDTH_MAX): a wider PNG fails with
/// "Invalid IHDR data".
inline constexpr std::size_t kPngMaxWidth = 1000000;

struct WaterfallOptions {
  Colormap colormap = Colormap::black_brown_yellow;  ///< grey writes one band, else RGB
  /// Resample each side to ground range on a flat bottom (columns = ground range, same spacing
  /// as the slant samples; the water column disappears).
  bool slant_correct = false;
  /// With slant_correct, in write_xtf_waterfall: where each ping's altitude comes from
  /// (docs/conversion.md; auto: the header's unless missing, <= 0 or disagreeing with the
  /// bottom tracked from the first return).
  AltitudeSource altitude_source = AltitudeSource::kAuto;
  /// Scaling: dB of the linear value mapped to [0, 1] between these percentiles of the image...
  double lo_percentile = 1.0;
  double hi_percentile = 99.0;
  /// The percentiles are those of a regular subsample of at most this many values of the image
  /// (robust_db_range's), >= 1: 4 bytes each while the image is written. 2^18 puts the 1st and
  /// 99th percentiles within +-0.1 percentile points of the whole image's (rank error
  /// sqrt(p (1 - p) / n) = 0.02 points, tests/waterfall_test.cpp).
  std::size_t range_samples = std::size_t{1} << 18;
  /// ...or between fixed dB values when fixed_db is true...
  bool fixed_db = false;
  double lo_db = 0.0;
  double hi_db = 90.0;
  /// ...or, when > 0, linearly: value / linear_full_scale (e.g. the samples' full scale, 32767
  /// for sonarsynth's u16: the founding paper's grey level, docs/paper-model.md).
  double linear_full_scale = 0.0;
  bool overwrite = false;
  /// Largest image (columns x rows) written: a longer line is decimated along track (each image
  /// row the mean of pings_per_row() consecutive pings) so that the image fits; add_ping throws
  /// InputError only if a single row is wider than this.
  std::size_t max_pixels = std::size_t{1} << 28;
  /// Widest row (port + starboard columns) accepted, 0 = no limit; add_file_pings refuses a
  /// wider ping naming the file before anything is spooled. write_xtf_waterfall sets
  /// kPngMaxWidth for a .png.
  std::size_t max_cols = 0;
  /// Where the rows wait for write() (an unnamed temporary file, see Waterfall); empty = the
  /// system's temporary directory.
  std::filesystem::path spool_dir;
  /// Metadata items written into the image (e.g. the run's run_metadata()); write() adds
  /// SONARSYNTH_VERSION, SONARSYNTH_QUANTITY, SONARSYNTH_UNITS, SONARSYNTH_DISPLAY_SCALE,
  /// SONARSYNTH_WATERFALL_LAYOUT and SONARSYNTH_NODATA. GeoTIFF: GDAL metadata; PNG: text chunks.
  std::vector<std::pair<std::string, std::string>> metadata;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Rows of a port | starboard waterfall in linear units: row = ping, columns = port FAR -> NEAR
/// then starboard NEAR -> FAR (nadir between columns n-1 and n); shorter sides are padded with
/// NaN (nodata, drawn black).
///
/// Memory does not grow with the number of rows: each row goes to a temporary file in
/// options.spool_dir (unlinked as soon as it is created, so nothing is left behind; its space
/// is freed when the Waterfall is destroyed) and write() streams the rows from it into the image
/// file. The file takes 4 bytes per sample plus 16 per row.
class Waterfall : public detail::SpooledRows {
 public:
  /// Throws InputError for invalid options, FormatError if the spool file cannot be created.
  explicit Waterfall(WaterfallOptions options = {});
  /// Appends one ping; samples NEAR -> FAR. With slant_correct, altitude_m > 0 is required
  /// (otherwise the row is added uncorrected) and slant_range_m is the range of the last sample.
  void add_ping(std::span<const float> port, std::span<const float> starboard, double slant_range_m,
                double altitude_m);
  /// Pings averaged into one image row: 1 while cols() x rows() <= max_pixels, else the smallest
  /// N with cols() x ceil(rows() / N) <= max_pixels.
  std::size_t pings_per_row() const;
  /// Rows of the image: ceil(rows() / pings_per_row()).
  std::size_t image_rows() const;
  /// Linear image, row-major, NaN = nodata (read back from the spool file: cols x image_rows()
  /// floats). Row k is the mean of pings k N .. k N + N - 1 (N = pings_per_row(); the last row
  /// the pings left), pixel by pixel over the pings that have a value there; NaN if none has.
  std::vector<float> image() const;
  /// Sees each image row as it is written: its index, linear values (NaN = nodata), display
  /// values in [0, 1] (NaN = nodata) and colours (1 or 3 bands, band-sequential, cols() each).
  using RowTap = std::function<void(std::size_t row, std::span<const float> linear,
                                    std::span<const float> display,
                                    std::span<const std::uint8_t> colour, std::size_t bands)>;
  /// Writes PNG (name ending .png) or GeoTIFF without georeferencing (.tif/.tiff) under a
  /// temporary name, renamed when complete. Throws FormatError naming the path. The percentile
  /// scaling is robust_db_range of the whole image (read from the spool in a first pass); the
  /// rows are then coloured and written one at a time, each shown to `tap` (if any) once.
  void write(const std::string& path, const RowTap& tap = {}) const;

 private:
  WaterfallOptions options_;
};

struct WaterfallResult {
  std::size_t pings = 0;          ///< pings drawn
  std::size_t pings_per_row = 1;  ///< > 1: the line was decimated to fit max_pixels
  std::size_t rows = 0;           ///< image rows
  std::size_t cols = 0;
  std::size_t pings_no_samples = 0;
  std::size_t pings_with_samples = 0;      ///< in the file (add_file_pings: before the ping range)
  std::size_t pings_tracked_altitude = 0;  ///< slant_correct: rows corrected with the tracked one
  std::uint64_t reader_anomalies = 0;      ///< reported by xtf::Reader (malformed packets skipped)
  std::vector<std::string> reader_anomaly_messages;  ///< the first of them (file, packet, value)
};

/// Adds to `wf` the pings of a sonar file (any listed format) that have port or starboard samples,
/// numbered from 0 among those, from first_ping to last_ping (-1: to the end). With
/// options.slant_correct each ping's altitude comes from options.altitude_source (the whole
/// file is bottom-tracked first unless it is kHeader; docs/conversion.md). Fills pings,
/// pings_no_samples, pings_with_samples (up to last_ping), pings_tracked_altitude and the
/// reader anomalies; throws FormatError for an unreadable file.
WaterfallResult add_file_pings(const std::filesystem::path& sonar_path, Waterfall& wf,
                               const WaterfallOptions& options, std::int64_t first_ping = 0,
                               std::int64_t last_ping = -1);

/// Waterfall of an XTF file (all pings with port or starboard samples, navigation not needed).
/// Throws FormatError for an unreadable file or one without sonar channels. Without a
/// spool_dir in `options`, the rows are spooled in the directory of `image_path`.
WaterfallResult write_xtf_waterfall(const std::filesystem::path& xtf_path,
                                    const std::string& image_path,
                                    const WaterfallOptions& options = {});

/// How the truth waterfall stores its grazing angle band (docs/labels.md, "Per-sample truth").
enum class TruthGrazing {
  /// Int32 GeoTIFF: the grazing angle in hundredths of a degree (band scale 0.01, offset 0:
  /// degrees = 0.01 x value, within 0.005 deg of the rendered angle), nodata -2147483648; class
  /// and object id exact integers.
  hundredths,
  /// Float32 GeoTIFF: the grazing angle in degrees as rendered, NaN nodata (ids exact below
  /// 2^24); 5-6x the file size.
  float32,
};

/// Per-sample truth aligned with the XTF samples (same rows and columns as the waterfall of
/// the same pings): band 1 "class" (SampleClass value, 255 = padding), band 2 "object_id" (0
/// seabed, -1 none), band 3 "grazing_angle_deg" (none: the nodata value of every band). Written
/// without georeferencing, as TruthGrazing says (Int32 hundredths of a degree by default), the
/// codes in metadata items SONARSYNTH_CLASS_CODES and SONARSYNTH_OBJECT_ID_CODES. Rows are spooled
/// to an unnamed temporary file in `spool_dir` like those of Waterfall (12 bytes per sample).
/// Ground control points of a truth waterfall (docs/labels.md, "Georeferencing the line
/// rasters"): where samples of some rows lie on the seabed, in EPSG:epsg (the scene's UTM zone).
/// The rasters stay in slant-range geometry, not an affine grid: the points let a GIS place them
/// approximately (a polynomial or thin-plate warp through them).
struct WaterfallGroundControl {
  int epsg = 0;
  struct Point {
    std::size_t row = 0;     ///< ping (image row)
    bool starboard = false;  ///< side
    std::size_t sample = 0;  ///< sample of the side, NEAR -> FAR
    double easting_m = 0.0;
    double northing_m = 0.0;
  };
  std::vector<Point> points;
};

class TruthWaterfall : public detail::SpooledRows {
 public:
  /// `spool_dir` empty = the system's temporary directory. Throws FormatError if the spool file
  /// cannot be created.
  explicit TruthWaterfall(const std::filesystem::path& spool_dir = {});
  /// Spans NEAR -> FAR; the three spans of a side must have the same size.
  void add_ping(std::span<const SampleClass> port_class, std::span<const SampleClass> stbd_class,
                std::span<const std::int32_t> port_id, std::span<const std::int32_t> stbd_id,
                std::span<const float> port_grazing_rad, std::span<const float> stbd_grazing_rad);
  /// Ground control points written into the rasters by write() and write_with_labels() (none
  /// by default). Every file also gets internal overviews when larger than 256 pixels a side
  /// (nearest for classes and ids, average for the grazing angle), laid out as GDAL's COG
  /// validator asks unless set_cog_layout(false).
  void set_ground_control(WaterfallGroundControl gcps) { gcps_ = std::move(gcps); }
  /// false (`--of GTiff`): plain tiled GeoTIFFs, each image first and its overviews after it.
  void set_cog_layout(bool cog_layout) { cog_layout_ = cog_layout; }
  /// The grazing angle's encoding in the files written (TruthGrazing::hundredths by default).
  void set_grazing(TruthGrazing grazing) { grazing_ = grazing; }
  /// `metadata`: items written before the writer's own (e.g. the run's run_metadata()).
  void write(const std::string& path, bool overwrite = false,
             const std::vector<std::pair<std::string, std::string>>& metadata = {}) const;
  /// As write(), and in the same pass over the rows the line's class (Byte) and instance
  /// (UInt32) label rasters of docs/labels.md at `class_path` and `instance_path`: the files the
  /// label waterfall of the same pings writes
  /// (formats/private/sonarsynth/formats/products/truth_labels.hpp), without a spool of their own.
  /// `tap` (if any) sees each row's class and instance labels once, in order, as they are made.
  using LabelRowTap = std::function<void(std::size_t row, std::span<const std::uint8_t> cls,
                                         std::span<const std::uint32_t> instance)>;
  void write_with_labels(const std::string& path, const std::string& class_path,
                         const std::string& instance_path, bool overwrite,
                         const std::vector<std::pair<std::string, std::string>>& metadata,
                         const LabelRowTap& tap = {}) const;

 private:
  // spool_'s bands: class, object id (the int32's bits, so that ids stay exact for the label
  // rasters), grazing (deg).
  WaterfallGroundControl gcps_;
  TruthGrazing grazing_ = TruthGrazing::hundredths;
  bool cog_layout_ = true;
};

}  // namespace sonarsynth
