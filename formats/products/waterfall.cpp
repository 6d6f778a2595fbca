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
#include "sonarsynth/formats/products/truth_labels.hpp"
#include "sonarsynth/formats/products/xtf_mosaic.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

/// The object id band of a truth spool holds the int32's bits: float copies move bits
/// unchanged, and no arithmetic touches the band before it is read back.
float id_bits(std::int32_t id) {
  return std::bit_cast<float>(id);
}

const float kTruthPads[3] = {255.0f, id_bits(-1), kNaNf};

/// The rows of a truth spool: the truth waterfall's (float32, 3 bands: class, id as a float,
/// grazing), and on request the class and instance label rows of the same row.
class TruthSpoolRows {
 public:
  TruthSpoolRows(const detail::SideSpool& spool, const TruthWaterfall::LabelRowTap& tap)
      : reader_(spool, kTruthPads), cols_(spool.cols()), row_(3 * cols_), ids_(cols_), tap_(tap) {}
  std::size_t cols() const { return cols_; }
  /// Reads row `index` (the next one, or the current one again).
  void at(std::size_t index) {
    if (index + 1 == read_) return;
    if (index != read_) throw std::logic_error("truth waterfall: rows requested out of order");
    if (!reader_.next(row_)) throw FormatError("truth waterfall: spool file ended early");
    ++read_;
    float* id = row_.data() + cols_;
    for (std::size_t i = 0; i < cols_; ++i) ids_[i] = std::bit_cast<std::int32_t>(id[i]);
  }
  void truth(float* out) const {
    std::copy(row_.begin(), row_.begin() + static_cast<std::ptrdiff_t>(cols_), out);
    for (std::size_t i = 0; i < cols_; ++i) out[cols_ + i] = static_cast<float>(ids_[i]);
    std::copy(row_.begin() + static_cast<std::ptrdiff_t>(2 * cols_), row_.end(), out + 2 * cols_);
  }
  /// The same row as Int32 bands: class, id, grazing in hundredths of a degree (rounded to
  /// nearest; kTruthNodata where NaN).
  void truth(std::int32_t* out) const {
    for (std::size_t i = 0; i < cols_; ++i) out[i] = static_cast<std::int32_t>(row_[i]);
    std::copy(ids_.begin(), ids_.end(), out + cols_);
    const float* deg = row_.data() + 2 * cols_;
    std::int32_t* g = out + 2 * cols_;
    for (std::size_t i = 0; i < cols_; ++i) {
      g[i] = std::isnan(deg[i])
                 ? kTruthNodata
                 : static_cast<std::int32_t>(std::lround(100.0 * static_cast<double>(deg[i])));
    }
  }
  static constexpr std::int32_t kTruthNodata = std::numeric_limits<std::int32_t>::min();
  /// The class and instance label rows of the current row (computed once per row).
  const std::uint8_t* classes() {
    label_row();
    return classes_.data();
  }
  const std::uint32_t* instances() {
    label_row();
    return instances_.data();
  }
  void rewind() {
    reader_.rewind();
    read_ = 0;
    labels_of_ = 0;
  }

 private:
  void label_row() {
    if (labels_of_ == read_) return;
    classes_.resize(cols_);
    instances_.resize(cols_);
    labels::waterfall_label_row(std::span(row_).first(cols_), ids_, classes_.data(),
                                instances_.data(), scratch_);
    labels_of_ = read_;
    if (tap_ && read_ > tapped_) {
      tap_(read_ - 1, classes_, instances_);
      tapped_ = read_;
    }
  }

  detail::SideSpool::Reader reader_;
  std::size_t cols_;
  std::vector<float> row_;
  std::vector<std::int32_t> ids_;
  std::vector<std::uint8_t> classes_;
  std::vector<std::uint32_t> instances_;
  labels::LabelRowScratch scratch_;
  std::size_t read_ = 0;       ///< rows read
  std::size_t labels_of_ = 0;  ///< label rows computed for rows [0, labels_of_)
  const TruthWaterfall::LabelRowTap& tap_;
  std::size_t tapped_ = 0;  ///< label rows shown to the tap
};

/// One raster of the rows of a TruthSpoolRows, which several such views may share (each asks
/// for its rows in order; the spool row is read once for all of them).
class TruthView final : public raster::RowSource {
 public:
  enum class Kind { truth, truth_int, class_code, instance };
  TruthView(TruthSpoolRows& rows, Kind kind) : rows_(rows), kind_(kind) {}
  void next(void* out) override {
    rows_.at(row_++);
    if (kind_ == Kind::truth) {
      rows_.truth(static_cast<float*>(out));
      return;
    }
    if (kind_ == Kind::truth_int) {
      rows_.truth(static_cast<std::int32_t*>(out));
      return;
    }
    if (kind_ == Kind::class_code) {
      std::copy_n(rows_.classes(), rows_.cols(), static_cast<std::uint8_t*>(out));
    } else {
      std::copy_n(rows_.instances(), rows_.cols(), static_cast<std::uint32_t*>(out));
    }
  }
  void rewind() override {
    rows_.rewind();
    row_ = 0;
  }

 private:
  TruthSpoolRows& rows_;
  Kind kind_;
  std::size_t row_ = 0;
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

Waterfall::~Waterfall() = default;
Waterfall::Waterfall(Waterfall&&) noexcept = default;
Waterfall& Waterfall::operator=(Waterfall&&) noexcept = default;

std::size_t Waterfall::rows() const {
  return spool_ ? spool_->rows() : 0;
}

std::size_t Waterfall::cols() const {
  return spool_ ? spool_->cols() : 0;
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

TruthWaterfall::TruthWaterfall(const std::filesystem::path& spool_dir)
    : spool_(std::make_unique<detail::SideSpool>(spool_dir, 3, "truth waterfall")) {}

TruthWaterfall::~TruthWaterfall() = default;
TruthWaterfall::TruthWaterfall(TruthWaterfall&&) noexcept = default;
TruthWaterfall& TruthWaterfall::operator=(TruthWaterfall&&) noexcept = default;

std::size_t TruthWaterfall::rows() const {
  return spool_ ? spool_->rows() : 0;
}

std::size_t TruthWaterfall::cols() const {
  return spool_ ? spool_->cols() : 0;
}

void TruthWaterfall::add_ping(std::span<const SampleClass> port_class,
                              std::span<const SampleClass> stbd_class,
                              std::span<const std::int32_t> port_id,
                              std::span<const std::int32_t> stbd_id,
                              std::span<const float> port_grazing_rad,
                              std::span<const float> stbd_grazing_rad) {
  if (port_id.size() != port_class.size() || port_grazing_rad.size() != port_class.size() ||
      stbd_id.size() != stbd_class.size() || stbd_grazing_rad.size() != stbd_class.size()) {
    throw InputError("truth waterfall: ping " + std::to_string(rows()) +
                     ": class, id and grazing spans of a side differ in size");
  }
  std::vector<float> values[2][3];  // side, band: class, id (its bits), grazing (deg)
  auto fill = [](std::vector<float>(&dst)[3], std::span<const SampleClass> c,
                 std::span<const std::int32_t> id, std::span<const float> g) {
    const std::size_t n = c.size();
    for (auto& band : dst) band.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      dst[0][i] = static_cast<float>(static_cast<std::uint8_t>(c[i]));
      dst[1][i] = id_bits(id[i]);
      dst[2][i] = static_cast<float>(deg_from_rad(static_cast<double>(g[i])));
    }
  };
  fill(values[0], port_class, port_id, port_grazing_rad);
  fill(values[1], stbd_class, stbd_id, stbd_grazing_rad);
  const std::span<const float> port[3] = {values[0][0], values[0][1], values[0][2]};
  const std::span<const float> stbd[3] = {values[1][0], values[1][1], values[1][2]};
  spool_->append(port, stbd);
}

namespace {

raster::RasterLabels truth_labels(const std::vector<std::pair<std::string, std::string>>& metadata,
                                  TruthGrazing grazing) {
  const bool hundredths = grazing == TruthGrazing::hundredths;
  raster::RasterLabels labels;
  labels.metadata = metadata;
  labels.metadata.insert(
      labels.metadata.end(),
      {{"SONARSYNTH_VERSION", kVersion},
       {"SONARSYNTH_QUANTITY",
        "per-sample truth of the XTF samples: class, object id, grazing angle"},
       {"SONARSYNTH_UNITS", "class: code, object_id: id, grazing_angle_deg: degrees"},
       {"SONARSYNTH_GRAZING_ENCODING",
        hundredths ? "Int32 hundredths of a degree: degrees = 0.01 x value (band scale 0.01, "
                     "offset 0), rounded to nearest; nodata -2147483648 = no seabed echo"
                   : "Float32 degrees; nodata NaN = no seabed echo"},
       {"SONARSYNTH_CLASS_CODES",
        "0 = water_column, 1 = seabed, 2 = object, 3 = shadow, 4 = no_seabed, 255 = padding"},
       {"SONARSYNTH_OBJECT_ID_CODES",
        "0 = seabed (class shadow: hidden by seabed relief alone), -1 = none (no echo and no "
        "shadow, or padding), > 0 = the scene object with that id (class shadow: the object that "
        "casts it, docs/labels.md)"},
       {"SONARSYNTH_WATERFALL_LAYOUT",
        "row = ping, columns = port far -> near | starboard near -> far, slant range"},
       {"SONARSYNTH_NODATA",
        std::string(hundredths ? "-2147483648" : "NaN") +
            " (grazing angle: no seabed echo); a shorter side is padded with class 255, id -1"}});
  labels.descriptions = {"class", "object_id", "grazing_angle_deg"};
  labels.units = {"", "", "deg"};
  labels.has_nodata = true;
  if (hundredths) {
    labels.nodata = static_cast<double>(std::numeric_limits<std::int32_t>::min());
    labels.scales = {kNaN, kNaN, 0.01};
    labels.offsets = {kNaN, kNaN, 0.0};
  } else {
    labels.nodata = std::numeric_limits<double>::quiet_NaN();
  }
  return labels;
}

// Band-interleaved tiles with horizontal differencing (lossless: on the 32-bit words): the
// class and id bands are long runs of equal values, the grazing angle varies smoothly along a
// row. Against pixel-interleaved tiles without a predictor this is 0.58x the size and ~0.7x
// the CPU (docs/benchmarks.md, "End to end with every product").
// Tiles of 256 x 64: a line's three rasters are written a row of tiles at a time
// (raster::stream_to_files). For 2 x 4096 samples a row of 256-row tiles held 35 MB; 64 rows
// hold 8.8 MB, for a truth file 6 % larger (32 rows: 4.4 MB, 12 % larger).
const std::vector<std::pair<std::string, std::string>> kTruthTiffOptions = {
    {"COMPRESS", "ZSTD"}, {"ZSTD_LEVEL", "1"},  {"PREDICTOR", "2"},     {"INTERLEAVE", "BAND"},
    {"TILED", "YES"},     {"BLOCKYSIZE", "64"}, {"BIGTIFF", "IF_SAFER"}};

/// The label rasters' options with the truth raster's tiles.
std::vector<std::pair<std::string, std::string>> label_options() {
  auto co = labels::label_tiff_options();
  co.emplace_back("BLOCKYSIZE", "64");
  return co;
}

}  // namespace

namespace {

/// The points of `g` as pixel/line (pixel centres) of a waterfall of `cols` columns.
raster::GroundControl pixel_gcps(const WaterfallGroundControl& g, std::size_t cols) {
  raster::GroundControl out;
  out.epsg = g.epsg;
  const std::size_t side = cols / 2;
  for (const WaterfallGroundControl::Point& p : g.points) {
    if (p.sample >= side) continue;
    const std::size_t col = p.starboard ? side + p.sample : side - 1 - p.sample;
    out.points.push_back({static_cast<double>(col) + 0.5, static_cast<double>(p.row) + 0.5,
                          p.easting_m, p.northing_m});
  }
  return out;
}

/// The streamed file of a raster, next to its temporary path: overviews are added to it, then
/// it is copied to the temporary path (raster::copy_adding_overviews).
std::string stream_path(const std::filesystem::path& temp) {
  return temp.string() + ".stream.tif";
}

const std::vector<std::string> kTruthResampling = {"NEAREST", "NEAREST", "AVERAGE"};

/// The creation options of the streamed file: the final file's tiles and layout, uncompressed
/// (it is read twice, for the overviews and by the copy, which compresses once).
std::vector<std::pair<std::string, std::string>> stream_options(
    const std::vector<std::pair<std::string, std::string>>& final_options) {
  std::vector<std::pair<std::string, std::string>> co;
  for (const auto& [k, v] : final_options) {
    if (k == "COMPRESS" || k == "PREDICTOR" || k == "ZSTD_LEVEL" || k == "ZLEVEL") continue;
    co.emplace_back(k, v);
  }
  co.emplace_back("COMPRESS", "NONE");
  return co;
}

}  // namespace

void TruthWaterfall::write(const std::string& path, bool overwrite,
                           const std::vector<std::pair<std::string, std::string>>& metadata) const {
  constexpr const char* kWho = "truth waterfall";
  if (rows() == 0 || cols() == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping to write");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, overwrite);
  const LabelRowTap none;
  TruthSpoolRows rows(*spool_, none);
  const bool hundredths = grazing_ == TruthGrazing::hundredths;
  TruthView source(rows, hundredths ? TruthView::Kind::truth_int : TruthView::Kind::truth);
  const std::string stream = stream_path(out.temp_path());
  raster::stream_to_file(source, cols(), this->rows(), 3, hundredths ? GDT_Int32 : GDT_Float32,
                         "GTiff", stream, stream_options(kTruthTiffOptions),
                         truth_labels(metadata, grazing_), kWho, path);
  raster::copy_adding_overviews(stream, out.temp_path().string(), kTruthResampling,
                                kTruthTiffOptions, pixel_gcps(gcps_, cols()), kWho, path,
                                cog_layout_);
  out.commit();
}

void TruthWaterfall::write_with_labels(
    const std::string& path, const std::string& class_path, const std::string& instance_path,
    bool overwrite, const std::vector<std::pair<std::string, std::string>>& metadata,
    const LabelRowTap& tap) const {
  constexpr const char* kWho = "truth waterfall";
  if (rows() == 0 || cols() == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping to write");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, overwrite);
  AtomicOutput class_out(class_path, overwrite);
  AtomicOutput instance_out(instance_path, overwrite);
  TruthSpoolRows rows(*spool_, tap);
  const bool hundredths = grazing_ == TruthGrazing::hundredths;
  TruthView truth(rows, hundredths ? TruthView::Kind::truth_int : TruthView::Kind::truth);
  TruthView classes(rows, TruthView::Kind::class_code);
  TruthView instances(rows, TruthView::Kind::instance);
  std::vector<raster::StreamTarget> targets(3);
  targets[0] = {&truth,
                3,
                hundredths ? GDT_Int32 : GDT_Float32,
                stream_path(out.temp_path()),
                stream_options(kTruthTiffOptions),
                truth_labels(metadata, grazing_),
                path};
  targets[1] = {&classes,
                1,
                GDT_Byte,
                stream_path(class_out.temp_path()),
                stream_options(label_options()),
                labels::waterfall_class_labels(metadata),
                class_path};
  targets[2] = {&instances,
                1,
                GDT_UInt32,
                stream_path(instance_out.temp_path()),
                stream_options(label_options()),
                labels::waterfall_instance_labels(metadata),
                instance_path};
  raster::stream_to_files(targets, cols(), this->rows(), "GTiff", kWho);
  // Overviews (classes and ids: nearest, so that an overview pixel's class and instance are
  // those of one sample; the grazing angle: average) and the ground control points.
  const raster::GroundControl gcps = pixel_gcps(gcps_, cols());
  raster::copy_adding_overviews(targets[0].temp_path, out.temp_path().string(), kTruthResampling,
                                kTruthTiffOptions, gcps, kWho, path, cog_layout_);
  raster::copy_adding_overviews(targets[1].temp_path, class_out.temp_path().string(), {"NEAREST"},
                                label_options(), gcps, kWho, class_path, cog_layout_);
  raster::copy_adding_overviews(targets[2].temp_path, instance_out.temp_path().string(),
                                {"NEAREST"}, label_options(), gcps, kWho, instance_path,
                                cog_layout_);
  out.commit();
  class_out.commit();
  instance_out.commit();
}

}  // namespace sonarsynth
