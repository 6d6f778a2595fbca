// SPDX-License-Identifier: MIT
// The truth waterfall of a line (class, object id, grazing angle per sample) and its label
// rasters, in the waterfall's column layout (docs/labels.md).
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/products/mosaic_blocks.hpp"
#include "sonarsynth/formats/products/row_spool.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

TruthWaterfall::TruthWaterfall(const std::filesystem::path& spool_dir)
    : SpooledRows(std::make_unique<detail::SideSpool>(spool_dir, 3, "truth waterfall")) {}

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
