// SPDX-License-Identifier: MIT
// Where the chips come from: the track of each line recorded while it renders and the
// provenance record of each chip (chips/chips.jsonl, docs/labels.md).
#include <algorithm>
#include <cmath>

#include "sonarsynth/formats/config/label_set_parts.hpp"

namespace sonarsynth::labels {
namespace label_parts {
namespace {

/// {"x_m", "y_m", "lat_deg", "lon_deg"} of a local point, or null if unknown.
Json ground_point(const LabelContext& context, double x_m, double y_m) {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return nullptr;
  Json p = {{"x_m", x_m}, {"y_m", y_m}};
  if (context.frame) {
    const Eigen::Vector2d en = context.frame->projected_from_local({x_m, y_m});
    const Geodetic g = context.frame->geodetic_from_local({x_m, y_m});
    p["easting_m"] = en.x();
    p["northing_m"] = en.y();
    p["lat_deg"] = deg_from_rad(g.lat_rad);
    p["lon_deg"] = deg_from_rad(g.lon_rad);
  }
  return p;
}

}  // namespace

ChipFrame chip_frame(const LabelImage& li, std::size_t rows, GDALDataset* image,
                     const LabelContext& context) {
  ChipFrame f;
  if (!li.line.empty()) {
    for (std::size_t l = 0; l < context.line_names.size(); ++l) {
      if (context.line_names[l] == li.line && context.tracks && l < context.tracks->size() &&
          (*context.tracks)[l].along_track_m.size() == rows) {
        f.track = &(*context.tracks)[l];
      }
    }
  } else if (image) {
    f.geo = image->GetGeoTransform(f.gt) == CE_None;
  }
  return f;
}

/// The provenance record of one chip (a line of chips/chips.jsonl, docs/labels.md).
Json chip_record(const std::string& file, const LabelImage& li, const ChipFrame& f,
                 const LabelContext& context, std::size_t top, std::size_t left, std::size_t size,
                 std::size_t cols, const std::vector<Piece>& pieces,
                 const std::vector<bool>& truncated) {
  Json r = {{"file", file}, {"source_image", li.image}, {"pixel_box", {left, top, size, size}}};
  const std::size_t crow = top + size / 2, ccol = left + size / 2;
  const std::size_t corner_px[4][2] = {{top, left},
                                       {top, left + size - 1},
                                       {top + size - 1, left + size - 1},
                                       {top + size - 1, left}};
  Json boxes = Json::array();
  if (!li.line.empty()) {
    const std::size_t side = cols / 2;
    const double dr = context.sample_spacing_m;
    r["line"] = li.line;
    r["pings"] = {top, top + size - 1};
    r["columns"] = {left, left + size - 1};
    Json sides = Json::array();
    if (left < side) {
      sides.push_back("port");
      // Port columns run FAR -> NEAR: column c is sample side - 1 - c (0 = nearest).
      r["port_samples"] = {side - std::min(side, left + size), side - 1 - left};
    }
    if (left + size > side) {
      sides.push_back("starboard");
      r["starboard_samples"] = {std::max(left, side) - side, left + size - 1 - side};
    }
    r["sides"] = sides;
    double x = NAN, y = NAN;
    if (f.track && f.track->ground_xy(crow, ccol, x, y)) r["centre"] = ground_point(context, x, y);
    Json corners = Json::array();
    for (const auto& c : corner_px) {
      x = y = NAN;
      if (f.track) f.track->ground_xy(c[0], c[1], x, y);
      corners.push_back(ground_point(context, x, y));
    }
    r["corners"] = corners;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Box& b = pieces[i].box;
      Json jb = {{"object_id", b.instance},
                 {"category_id", b.category},
                 {"truncated", truncated[i] ? 1 : 0},
                 {"bbox_px", {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0}}};
      if (f.track) {
        jb["along_track_m"] = {f.track->along_track_m[top + b.y0],
                               f.track->along_track_m[top + b.y1 - 1]};
      }
      // Signed slant range of the box's column edges: port negative, starboard positive.
      jb["across_track_slant_m"] = {
          (static_cast<double>(left + b.x0) - static_cast<double>(side)) * dr,
          (static_cast<double>(left + b.x1) - static_cast<double>(side)) * dr};
      boxes.push_back(std::move(jb));
    }
  } else if (f.geo) {
    const auto east = [&](double col) { return f.gt[0] + col * f.gt[1] + 0.0 * f.gt[2]; };
    const auto north = [&](double row) { return f.gt[3] + row * f.gt[5]; };
    const auto point = [&](double col, double row) {
      const Eigen::Vector2d en(east(col), north(row));
      if (!context.frame) return Json{{"easting_m", en.x()}, {"northing_m", en.y()}};
      const Eigen::Vector2d xy = context.frame->local_from_projected(en);
      return ground_point(context, xy.x(), xy.y());
    };
    r["centre"] = point(static_cast<double>(ccol) + 0.5, static_cast<double>(crow) + 0.5);
    Json corners = Json::array();
    for (const auto& c : corner_px) {
      corners.push_back(point(static_cast<double>(c[1]) + 0.5, static_cast<double>(c[0]) + 0.5));
    }
    r["corners"] = corners;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Box& b = pieces[i].box;
      const auto x0 = static_cast<double>(left + b.x0), x1 = static_cast<double>(left + b.x1);
      const auto y0 = static_cast<double>(top + b.y0), y1 = static_cast<double>(top + b.y1);
      boxes.push_back(
          {{"object_id", b.instance},
           {"category_id", b.category},
           {"truncated", truncated[i] ? 1 : 0},
           {"bbox_px", {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0}},
           {"easting_m", {std::min(east(x0), east(x1)), std::max(east(x0), east(x1))}},
           {"northing_m", {std::min(north(y0), north(y1)), std::max(north(y0), north(y1))}}});
    }
  }
  r["boxes"] = boxes;
  return r;
}

}  // namespace label_parts

bool LineTrack::ground_xy(std::size_t row, std::size_t column, double& x_m, double& y_m) const {
  const auto it = std::lower_bound(columns.begin(), columns.end(), column);
  if (it == columns.end() || *it != column || row >= along_track_m.size()) return false;
  const std::size_t i = row * columns.size() + static_cast<std::size_t>(it - columns.begin());
  x_m = ground_x_m[i];
  y_m = ground_y_m[i];
  return true;
}

std::vector<std::size_t> chip_columns(std::size_t cols, const LabelSetOptions& options) {
  std::vector<std::size_t> out;
  const std::size_t size = options.chip_size_px, stride = options.chip_stride_px;
  for (std::size_t left = 0; left + size <= cols; left += stride) {
    out.insert(out.end(), {left, left + size / 2, left + size - 1});
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

TrackRecorder::TrackRecorder(std::size_t lines, std::size_t side, std::vector<std::size_t> columns)
    : side_(side), columns_(std::move(columns)), tracks_(lines) {}

void TrackRecorder::begin_line(std::size_t line) {
  if (line >= tracks_.size()) tracks_.resize(line + 1);
  current_ = &tracks_[line];
  current_->columns = columns_;
}

void TrackRecorder::ping(const RenderedPing& p) {
  // The rows of the label rasters: the pings with truth (formats/products/survey_products.cpp).
  if (!current_ || p.port.truth_class.empty()) return;
  LineTrack& t = *current_;
  const Eigen::Vector2d xy = p.pose.sensor_xy_m;
  t.along_track_m.push_back(
      t.along_track_m.empty() ? 0.0 : t.along_track_m.back() + (xy - last_xy_).norm());
  last_xy_ = xy;
  for (const std::size_t c : columns_) {
    // Port columns run FAR -> NEAR (column c is port sample side - 1 - c), starboard NEAR -> FAR.
    const SideOutput& s = c < side_ ? p.port : p.starboard;
    const std::size_t k = c < side_ ? side_ - 1 - c : c - side_;
    const Eigen::Vector2d g = k < s.truth_ground_range_m.size()
                                  ? s.truth_ground_xy(k)
                                  : Eigen::Vector2d::Constant(SideOutput::kNoPosition);
    t.ground_x_m.push_back(g.x());
    t.ground_y_m.push_back(g.y());
  }
}

}  // namespace sonarsynth::labels
