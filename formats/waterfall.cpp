// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/waterfall.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include "raster_util.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/atomic_file.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"

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

template <typename Row, typename Get>
void assemble(const std::vector<Row>& rows, std::size_t side, Get get, float pad,
              std::vector<float>& out) {
  const std::size_t cols = 2 * side;
  out.assign(cols * rows.size(), pad);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto& [port, stbd] = get(rows[r]);
    float* row = out.data() + r * cols;
    for (std::size_t i = 0; i < port.size(); ++i) row[side - 1 - i] = port[i];
    std::copy(stbd.begin(), stbd.end(), row + side);
  }
}

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
  }
  if (!os.str().empty()) throw InputError(os.str());
}

Waterfall::Waterfall(WaterfallOptions options) : options_(options) {
  options_.validate();
}

void Waterfall::add_ping(std::span<const float> port, std::span<const float> starboard,
                         double slant_range_m, double altitude_m) {
  Row row;
  const bool correct = options_.slant_correct && altitude_m > 0.0 && slant_range_m > 0.0 &&
                       std::isfinite(altitude_m) && std::isfinite(slant_range_m);
  if (correct) {
    if (!port.empty()) row.port = ground_resample(port, slant_range_m, altitude_m);
    if (!starboard.empty()) row.starboard = ground_resample(starboard, slant_range_m, altitude_m);
  } else {
    row.port.assign(port.begin(), port.end());
    row.starboard.assign(starboard.begin(), starboard.end());
  }
  const std::size_t side = std::max({side_, port.size(), starboard.size()});
  if (2 * side * (rows_.size() + 1) > options_.max_pixels) {
    throw InputError("waterfall: image of " + std::to_string(2 * side) + " x " +
                     std::to_string(rows_.size() + 1) +
                     " pixels exceeds max_pixels = " + std::to_string(options_.max_pixels));
  }
  side_ = side;
  rows_.push_back(std::move(row));
}

std::vector<float> Waterfall::image() const {
  std::vector<float> out;
  assemble(
      rows_, side_, [](const Row& r) { return std::tie(r.port, r.starboard); }, kNaNf, out);
  return out;
}

void Waterfall::write(const std::string& path) const {
  constexpr const char* kWho = "waterfall";
  const std::string driver = driver_for(path, kWho);
  if (rows_.empty() || side_ == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping with samples to draw");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, options_.overwrite);
  const std::vector<float> img = image();
  const DisplayRange range =
      options_.fixed_db ? DisplayRange{options_.lo_db, options_.hi_db}
                        : robust_db_range(img, options_.lo_percentile, options_.hi_percentile);
  const bool grey = options_.colormap == Colormap::grey;
  const int bands = grey ? 1 : 3;
  const std::size_t n = img.size();
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(bands) * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = range.value(img[i]);
    if (std::isnan(v)) continue;  // nodata: black
    const Rgb8 c = colormap(options_.colormap, v);
    bytes[i] = c.r;
    if (!grey) {
      bytes[n + i] = c.g;
      bytes[2 * n + i] = c.b;
    }
  }
  gdal::DatasetPtr mem = raster::create_mem(cols(), rows(), bands, GDT_Byte, kWho, path);
  for (int b = 0; b < bands; ++b) {
    raster::write_band(*mem, b + 1, bytes.data() + static_cast<std::size_t>(b) * n, GDT_Byte, kWho,
                       path);
  }
  std::vector<std::pair<std::string, std::string>> co;
  // Fast compression: waterfalls are large and written once per line.
  if (driver == "GTiff") co = {{"COMPRESS", "ZSTD"}, {"ZSTD_LEVEL", "1"}, {"TILED", "YES"}};
  if (driver == "PNG") co = {{"ZLEVEL", "1"}};
  raster::copy_to_file(*mem, driver.c_str(), out.temp_path().string(), co, kWho, path);
  out.commit();
}

WaterfallResult write_xtf_waterfall(const std::filesystem::path& xtf_path,
                                    const std::string& image_path,
                                    const WaterfallOptions& options) {
  driver_for(image_path, "waterfall");  // fail on a bad extension before reading anything
  if (!options.overwrite && std::filesystem::exists(image_path)) {
    throw FormatError("waterfall: " + image_path + " already exists (use overwrite to replace it)");
  }
  Waterfall wf(options);
  WaterfallResult result;
  xtf::Reader reader(xtf_path);
  xtf::Packet packet;
  while (reader.next(packet)) {
    if (packet.kind != xtf::PacketKind::kPing) continue;
    const xtf::SonarPing& s = packet.ping.sonar;
    if (s.port.empty() && s.starboard.empty()) {
      ++result.pings_no_samples;
      continue;
    }
    wf.add_ping(s.port, s.starboard, s.slant_range_m, s.altitude_m);
  }
  if (wf.rows() == 0) {
    throw FormatError("waterfall: " + xtf_path.string() +
                      ": no sonar channel (no ping has port or starboard samples)");
  }
  wf.write(image_path);
  result.rows = wf.rows();
  result.cols = wf.cols();
  return result;
}

void TruthWaterfall::add_ping(std::span<const SampleClass> port_class,
                              std::span<const SampleClass> stbd_class,
                              std::span<const std::int32_t> port_id,
                              std::span<const std::int32_t> stbd_id,
                              std::span<const float> port_grazing_rad,
                              std::span<const float> stbd_grazing_rad) {
  if (port_id.size() != port_class.size() || port_grazing_rad.size() != port_class.size() ||
      stbd_id.size() != stbd_class.size() || stbd_grazing_rad.size() != stbd_class.size()) {
    throw InputError("truth waterfall: ping " + std::to_string(rows_.size()) +
                     ": class, id and grazing spans of a side differ in size");
  }
  Row row;
  auto fill = [](std::vector<float>(&dst)[3], std::span<const SampleClass> c,
                 std::span<const std::int32_t> id, std::span<const float> g) {
    for (std::size_t i = 0; i < c.size(); ++i) {
      dst[0].push_back(static_cast<float>(static_cast<std::uint8_t>(c[i])));
      dst[1].push_back(static_cast<float>(id[i]));
      dst[2].push_back(static_cast<float>(deg_from_rad(static_cast<double>(g[i]))));
    }
  };
  fill(row.port, port_class, port_id, port_grazing_rad);
  fill(row.starboard, stbd_class, stbd_id, stbd_grazing_rad);
  side_ = std::max({side_, port_class.size(), stbd_class.size()});
  rows_.push_back(std::move(row));
}

void TruthWaterfall::write(const std::string& path, bool overwrite) const {
  constexpr const char* kWho = "truth waterfall";
  if (rows_.empty() || side_ == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping to write");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, overwrite);
  gdal::DatasetPtr mem = raster::create_mem(cols(), rows(), 3, GDT_Float32, kWho, path);
  const char* names[3] = {"class", "object id", "grazing angle (degrees)"};
  const float pads[3] = {255.0f, -1.0f, kNaNf};
  std::vector<float> band;
  for (int b = 0; b < 3; ++b) {
    const auto k = static_cast<std::size_t>(b);
    assemble(
        rows_, side_, [k](const Row& r) { return std::tie(r.port[k], r.starboard[k]); }, pads[b],
        band);
    GDALRasterBand* gb = mem->GetRasterBand(b + 1);
    gb->SetDescription(names[b]);
    if (b == 2) gb->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
    raster::write_band(*mem, b + 1, band.data(), GDT_Float32, kWho, path);
  }
  raster::copy_to_file(
      *mem, "GTiff", out.temp_path().string(),
      {{"COMPRESS", "ZSTD"}, {"ZSTD_LEVEL", "1"}, {"TILED", "YES"}, {"BIGTIFF", "IF_SAFER"}}, kWho,
      path);
  out.commit();
}

}  // namespace sonarsynth
