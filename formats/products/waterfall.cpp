// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/waterfall.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/products/mosaic_blocks.hpp"
#include "sonarsynth/formats/products/row_spool.hpp"
#include "sonarsynth/formats/products/xtf_mosaic.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

/// Flat-bottom ground-range resampling of one side: output column j at ground range
/// (j + 0.5) dr, value interpolated linearly at slant range sqrt(y^2 + A^2); NaN beyond.
std::vector<float> ground_resample(std::span<const float> s, double slant_range_m,
                                   double altitude_m) {
  const std::size_t n = s.size();
  std::vector<float> out(n, kNaNf);
  const double dr = slant_range_m / static_cast<double>(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double y = (static_cast<double>(j) + 0.5) * dr;
    const double u = std::hypot(y, altitude_m) / dr - 0.5;  // fractional sample index
    if (u > static_cast<double>(n) - 0.5) break;
    const double uc = std::clamp(u, 0.0, static_cast<double>(n - 1));
    const auto i0 = static_cast<std::size_t>(uc);
    const std::size_t i1 = std::min(i0 + 1, n - 1);
    const double t = uc - static_cast<double>(i0);
    out[j] = static_cast<float>((1.0 - t) * s[i0] + t * s[i1]);
  }
  return out;
}

std::string driver_for(const std::string& path, const char* who) {
  const std::string ext = raster::lower_extension(path);
  if (ext == ".png") return "PNG";
  if (ext == ".tif" || ext == ".tiff") return "GTiff";
  throw InputError(std::string(who) + ": output " + path +
                   ": unsupported extension (use .png or .tif)");
}

/// The image rows of a waterfall from its spool: each the mean (linear) of `per_row`
/// consecutive pings, NaN where none of them has a sample; the last row takes what is left.
class MeanRows {
 public:
  MeanRows(const detail::SideSpool& spool, std::size_t per_row)
      : reader_(spool, std::span<const float>(&kNaNf, 1)),
        per_row_(per_row),
        ping_(spool.cols()),
        sum_(spool.cols()),
        count_(spool.cols()) {}
  /// Fills `out` (cols values) with the next image row; false after the last.
  bool next(std::span<float> out) {
    if (per_row_ == 1) return reader_.next(out);
    std::fill(sum_.begin(), sum_.end(), 0.0);
    std::fill(count_.begin(), count_.end(), std::uint32_t{0});
    std::size_t pings = 0;
    while (pings < per_row_ && reader_.next(ping_)) {
      ++pings;
      for (std::size_t i = 0; i < ping_.size(); ++i) {
        if (std::isnan(ping_[i])) continue;
        sum_[i] += static_cast<double>(ping_[i]);
        ++count_[i];
      }
    }
    if (pings == 0) return false;
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = count_[i] > 0 ? static_cast<float>(sum_[i] / count_[i]) : kNaNf;
    }
    return true;
  }
  void rewind() { reader_.rewind(); }

 private:
  detail::SideSpool::Reader reader_;
  std::size_t per_row_;
  std::vector<float> ping_;
  std::vector<double> sum_;
  std::vector<std::uint32_t> count_;
};

/// The coloured rows of a waterfall (u8, 1 or 3 bands) from its spool.
class ColouredRows final : public raster::RowSource {
 public:
  ColouredRows(const detail::SideSpool& spool, std::size_t per_row, DisplayRange range,
               Colormap map, const Waterfall::RowTap& tap)
      : reader_(spool, per_row), range_(range), map_(map), linear_(spool.cols()), tap_(tap) {}
  void next(void* out) override {
    if (!reader_.next(linear_)) throw FormatError("waterfall: spool file ended early");
    const std::size_t n = linear_.size();
    auto* red = static_cast<std::uint8_t*>(out);
    if (map_ == Colormap::grey) {
      for (std::size_t i = 0; i < n; ++i) red[i] = colour(linear_[i]).r;
    } else {
      std::uint8_t* green = red + n;
      std::uint8_t* blue = green + n;
      for (std::size_t i = 0; i < n; ++i) {
        const Colour& c = colour(linear_[i]);
        red[i] = c.r;
        green[i] = c.g;
        blue[i] = c.b;
      }
    }
    if (tap_ && row_ == tapped_) {
      display_.resize(n);
      for (std::size_t i = 0; i < n; ++i) display_[i] = colour(linear_[i]).display;
      const std::size_t bands = map_ == Colormap::grey ? 1 : 3;
      tap_(row_, linear_, display_, {red, bands * n}, bands);
      ++tapped_;
    }
    ++row_;
  }
  void rewind() override {
    reader_.rewind();
    row_ = 0;
  }

 private:
  /// 12 bytes, so that the cache stays small: the float it is the colour of, its display value
  /// (NaN for nodata) and the colour (black for nodata: the colour of a pixel without a sample).
  struct Colour {
    std::uint32_t bits = 0;
    float display = 0.0f;
    std::uint8_t r = 0, g = 0, b = 0;
    bool known = false;
  };
  /// The colour of `value`, remembered by its bits: samples repeat (quantised), and the colour
  /// is a function of the value alone, so a remembered one is the one computed afresh.
  const Colour& colour(float value) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    Colour& c = cache_[(bits ^ (bits >> 16)) & (kCacheSize - 1)];
    if (c.known && c.bits == bits) return c;
    const double v = range_.value(value);
    const Rgb8 rgb = std::isnan(v) ? Rgb8{} : colormap(map_, v);
    c.bits = bits;
    c.display = static_cast<float>(v);
    c.known = true;
    c.r = rgb.r;
    c.g = rgb.g;
    c.b = rgb.b;
    return c;
  }
  static constexpr std::size_t kCacheSize = std::size_t{1} << 16;

  MeanRows reader_;
  DisplayRange range_;
  Colormap map_;
  std::vector<float> linear_;
  const Waterfall::RowTap& tap_;
  std::vector<float> display_;
  std::size_t row_ = 0, tapped_ = 0;  ///< rows read (this pass), rows shown to the tap
  std::vector<Colour> cache_ = std::vector<Colour>(kCacheSize);
};

}  // namespace

void WaterfallOptions::validate() const {
  std::ostringstream os;
  if (!fixed_db &&
      !(lo_percentile >= 0.0 && lo_percentile < hi_percentile && hi_percentile <= 100.0)) {
    os << "waterfall: lo_percentile = " << lo_percentile << ", hi_percentile = " << hi_percentile
       << ". Violated constraint: 0 <= lo_percentile < hi_percentile <= 100";
  } else if (fixed_db && !(std::isfinite(lo_db) && std::isfinite(hi_db) && lo_db < hi_db)) {
    os << "waterfall: lo_db = " << lo_db << ", hi_db = " << hi_db
       << ". Violated constraint: finite lo_db < hi_db";
  } else if (max_pixels == 0) {
    os << "waterfall: max_pixels = 0. Violated constraint: max_pixels > 0";
  } else if (range_samples == 0) {
    os << "waterfall: range_samples = 0. Violated constraint: range_samples > 0";
  } else if (!(linear_full_scale >= 0.0 && std::isfinite(linear_full_scale))) {
    os << "waterfall: linear_full_scale = " << linear_full_scale
       << ". Violated constraint: linear_full_scale >= 0 (0 = dB scaling)";
  }
  if (!os.str().empty()) throw InputError(os.str());
}

Waterfall::Waterfall(WaterfallOptions options) : options_(std::move(options)) {
  options_.validate();
  spool_ = std::make_unique<detail::SideSpool>(options_.spool_dir, 1, "waterfall");
}

std::size_t Waterfall::pings_per_row() const {
  const std::size_t c = cols(), r = rows();
  if (c == 0 || r == 0 || c * r <= options_.max_pixels) return 1;
  const std::size_t rows_that_fit = options_.max_pixels / c;  // >= 1 (checked by add_ping)
  return (r + rows_that_fit - 1) / rows_that_fit;
}

std::size_t Waterfall::image_rows() const {
  const std::size_t n = pings_per_row();
  return (rows() + n - 1) / n;
}

void Waterfall::add_ping(std::span<const float> port, std::span<const float> starboard,
                         double slant_range_m, double altitude_m) {
  const std::size_t side = std::max({spool_->side(), port.size(), starboard.size()});
  if (2 * side > options_.max_pixels) {
    throw InputError("waterfall: ping " + std::to_string(rows()) + ": a row of " +
                     std::to_string(2 * side) +
                     " pixels exceeds max_pixels = " + std::to_string(options_.max_pixels));
  }
  const bool correct = options_.slant_correct && altitude_m > 0.0 && slant_range_m > 0.0 &&
                       std::isfinite(altitude_m) && std::isfinite(slant_range_m);
  std::vector<float> port_ground, stbd_ground;
  if (correct) {
    if (!port.empty()) port = port_ground = ground_resample(port, slant_range_m, altitude_m);
    if (!starboard.empty()) {
      starboard = stbd_ground = ground_resample(starboard, slant_range_m, altitude_m);
    }
  }
  spool_->append(std::span(&port, 1), std::span(&starboard, 1));
}

std::vector<float> Waterfall::image() const {
  if (!spool_) return {};  // moved from
  const std::size_t cols = this->cols();
  std::vector<float> out(cols * image_rows());
  MeanRows reader(*spool_, pings_per_row());
  for (std::size_t r = 0; r < image_rows(); ++r) {
    if (!reader.next(std::span(out).subspan(r * cols, cols))) break;
  }
  return out;
}

void Waterfall::write(const std::string& path, const RowTap& tap) const {
  constexpr const char* kWho = "waterfall";
  const std::string driver = driver_for(path, kWho);
  if (rows() == 0 || cols() == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping with samples to draw");
  }
  if (driver == "PNG" && cols() > kPngMaxWidth) {
    throw InputError(std::string(kWho) + ": " + path + ": " + std::to_string(cols()) +
                     " columns exceed libpng's width limit of " + std::to_string(kPngMaxWidth) +
                     "; write a .tif instead");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, options_.overwrite);
  const std::size_t per_row = pings_per_row();
  DisplayRange range{options_.lo_db, options_.hi_db, options_.linear_full_scale};
  const bool linear = options_.linear_full_scale > 0.0;
  if (!options_.fixed_db && !linear) {
    // First pass: the subsample robust_db_range would take of the whole image.
    DbRangeSampler sampler(cols() * image_rows(), options_.range_samples);
    MeanRows reader(*spool_, per_row);
    std::vector<float> row(cols());
    while (reader.next(row)) sampler.add(row);
    range = sampler.range(options_.lo_percentile, options_.hi_percentile);
  }
  const bool grey = options_.colormap == Colormap::grey;
  const int bands = grey ? 1 : 3;
  ColouredRows source(*spool_, per_row, range, options_.colormap, tap);
  // Fast compression: waterfalls are large and written once per line.
  const std::vector<std::pair<std::string, std::string>> co = {
      {"COMPRESS", "ZSTD"}, {"ZSTD_LEVEL", "1"}, {"TILED", "YES"}};
  raster::RasterLabels labels;
  labels.metadata = options_.metadata;
  std::ostringstream scale;
  scale << range.describe() << ", ";
  if (options_.fixed_db || linear) {
    scale << "fixed";
  } else {
    scale << "percentiles " << options_.lo_percentile << " / " << options_.hi_percentile;
  }
  std::ostringstream layout;
  layout << "row = " << per_row << (per_row == 1 ? " ping" : " pings (mean)")
         << ", columns = port far -> near | starboard near -> far, "
         << (options_.slant_correct ? "flat-bottom ground range" : "slant range");
  labels.metadata.insert(
      labels.metadata.end(),
      {{"SONARSYNTH_VERSION", kVersion},
       {"SONARSYNTH_QUANTITY", std::string("display colour: ") +
                                   (grey ? "grey" : "black-brown-yellow") + " colormap of the " +
                                   (linear ? "linear" : "dB") + " value of the samples"},
       {"SONARSYNTH_UNITS", "none (8-bit colour)"},
       {"SONARSYNTH_DISPLAY_SCALE", scale.str()},
       {"SONARSYNTH_WATERFALL_LAYOUT", layout.str()},
       {"SONARSYNTH_NODATA", "0 (black): no sample"}});
  labels.descriptions =
      grey ? std::vector<std::string>{"grey"} : std::vector<std::string>{"red", "green", "blue"};
  if (driver == "PNG") {
    // A PNG keeps the metadata items in text chunks (the only place it has for them); it has
    // no place for band descriptions.
    raster::stream_to_png(source, cols(), image_rows(), bands, labels.metadata,
                          out.temp_path().string(), kWho, path);
  } else {
    raster::stream_to_file(source, cols(), image_rows(), bands, GDT_Byte, driver.c_str(),
                           out.temp_path().string(), co, labels, kWho, path);
  }
  out.commit();
}

WaterfallResult add_file_pings(const std::filesystem::path& sonar_path, Waterfall& wf,
                               const WaterfallOptions& options, std::int64_t first_ping,
                               std::int64_t last_ping) {
  WaterfallResult result;
  const std::unique_ptr<SideScanSource> reader = SideScanSource::open(sonar_path);
  const bool track = options.slant_correct && options.altitude_source != AltitudeSource::kHeader;
  const std::vector<double> tracked =
      track ? track_file_altitudes(sonar_path) : std::vector<double>{};
  SideScanRecord rec;
  std::size_t k = 0;       // pings with samples and a positive slant range: as the tracker counts
  std::int64_t index = 0;  // pings with samples
  while (reader->next(rec)) {
    const SonarPing& s = rec.sonar;
    if (s.port.empty() && s.starboard.empty()) {
      ++result.pings_no_samples;
      continue;
    }
    if (last_ping >= 0 && index > last_ping) break;
    double altitude_m = s.altitude_m;
    bool tracked_altitude = false;
    if (options.slant_correct && s.slant_range_m > 0.0 && std::isfinite(s.slant_range_m)) {
      const double t = k < tracked.size() ? tracked[k] : std::nan("");
      ++k;
      const std::size_t n = std::max(s.port.size(), s.starboard.size());
      const AltitudeChoice a = choose_altitude(options.altitude_source, s.altitude_m, t,
                                               s.slant_range_m / static_cast<double>(n));
      altitude_m = a.altitude_m;
      tracked_altitude = a.tracked;
    }
    if (index >= first_ping) {
      const std::size_t width = 2 * std::max(s.port.size(), s.starboard.size());
      if (options.max_cols > 0 && width > options.max_cols) {
        throw InputError("waterfall: " + sonar_path.string() + ": ping " + std::to_string(index) +
                         " (ping number " + std::to_string(s.ping_number) + "): a row of " +
                         std::to_string(width) + " pixels (2 x " + std::to_string(width / 2) +
                         " samples) exceeds the image's width limit of " +
                         std::to_string(options.max_cols) +
                         " (libpng's, for a .png); write a .tif instead");
      }
      wf.add_ping(s.port, s.starboard, s.slant_range_m, altitude_m);
      ++result.pings;
      result.pings_tracked_altitude += tracked_altitude ? 1 : 0;
    }
    ++index;
  }
  result.pings_with_samples = static_cast<std::size_t>(index);
  result.reader_anomalies = reader->total_anomalies();
  result.reader_anomaly_messages = reader->anomaly_messages(10);
  return result;
}

WaterfallResult write_xtf_waterfall(const std::filesystem::path& xtf_path,
                                    const std::string& image_path,
                                    const WaterfallOptions& options) {
  driver_for(image_path, "waterfall");  // fail on a bad extension before reading anything
  if (!options.overwrite && std::filesystem::exists(image_path)) {
    throw FormatError("waterfall: " + image_path + " already exists (use overwrite to replace it)");
  }
  // Spool next to the image: the file system that is to receive it, rather than a /tmp that
  // may be in memory (unless asked otherwise, or the directory is missing: then the write
  // reports it).
  WaterfallOptions wo = options;
  if (wo.spool_dir.empty()) {
    std::filesystem::path dir = std::filesystem::path(image_path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (std::filesystem::is_directory(dir, ec)) wo.spool_dir = dir;
  }
  if (driver_for(image_path, "waterfall") == "PNG") {
    wo.max_cols = wo.max_cols == 0 ? kPngMaxWidth : std::min(wo.max_cols, kPngMaxWidth);
  }
  Waterfall wf(wo);
  WaterfallResult result = add_file_pings(xtf_path, wf, wo);
  if (wf.rows() == 0) {
    throw FormatError("waterfall: " + xtf_path.string() +
                      ": no sonar channel (no ping has port or starboard samples)");
  }
  wf.write(image_path);
  result.pings = wf.rows();
  result.pings_per_row = wf.pings_per_row();
  result.rows = wf.image_rows();
  result.cols = wf.cols();
  return result;
}

}  // namespace sonarsynth
