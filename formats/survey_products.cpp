// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/survey_products.hpp"

#include <chrono>
#include <cmath>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

void SurveyProductOptions::validate() const {
  if (!(mosaic_pixel_m > 0.0) || !std::isfinite(mosaic_pixel_m)) {
    throw InputError("products: mosaic pixel = " + std::to_string(mosaic_pixel_m) +
                     " m. Violated constraint: pixel > 0");
  }
  mosaic_options.validate();
  if (mosaic) write_options.validate();  // creation options: refused before any rendering
}

SurveyProducts::SurveyProducts(std::filesystem::path dir, std::shared_ptr<const Scene> shared_scene,
                               const SonarConfig& sonar, const std::vector<SurveyLine>& lines,
                               SurveyProductOptions options)
    : dir_(std::move(dir)),
      scene_(std::move(shared_scene)),
      sonar_(sonar),
      options_(std::move(options)) {
  if (!scene_) throw InputError("products: scene = null. Violated constraint: a scene");
  const Scene& scene = *scene_;
  options_.validate();
  // One ping must fit in a waterfall row: checked before anything is rendered.
  if (options_.waterfalls && 2 * sonar.samples_per_channel > options_.waterfall_max_pixels) {
    throw InputError(
        "products: waterfall max pixels = " + std::to_string(options_.waterfall_max_pixels) +
        ". Violated constraint: at least one row of 2 x samples = " +
        std::to_string(2 * sonar.samples_per_channel) + " pixels");
  }
  for (const SurveyLine& l : lines) names_.push_back(l.name);
  if (options_.mosaic) {
    Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    for (const SurveyLine& l : lines) {
      for (const Eigen::Vector2d& p : l.waypoints_xy_m) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    // The swath reaches at most the slant range to either side; clip to the bathymetry.
    const Eigen::Vector4d bb = scene.bathymetry.bounds();
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(sonar.max_range_m);
    lo = (lo - r).cwiseMax(Eigen::Vector2d(bb[0], bb[1]));
    hi = (hi + r).cwiseMin(Eigen::Vector2d(bb[2], bb[3]));
    if (!(lo.x() < hi.x() && lo.y() < hi.y())) {
      throw InputError("products: the survey lines do not overlap the bathymetry grid");
    }
    mosaic_ =
        std::make_unique<MosaicGrid>(MosaicGrid::geometry_covering(lo, hi, options_.mosaic_pixel_m),
                                     options_.mosaic_options, &scene.bathymetry);
  }
}

void SurveyProducts::begin_line(std::size_t /*line*/) {
  // Rows are spooled next to the outputs (the same file system; the spool files are unnamed).
  if (options_.waterfalls) {
    WaterfallOptions wo;
    wo.spool_dir = dir_;
    wo.max_pixels = options_.waterfall_max_pixels;
    wo.linear_full_scale = options_.display_linear_full_scale;
    wo.metadata = options_.write_options.metadata;  // the run's items, in every product
    waterfall_ = std::make_unique<Waterfall>(wo);
  }
  if (options_.truth) truth_ = std::make_unique<TruthWaterfall>(dir_);
  if (mosaic_) mosaic_->break_line();
}

void SurveyProducts::ping(const RenderedPing& p) {
  const PingPose& pose = p.pose;
  if (mosaic_) {
    MosaicPing m;
    m.sensor_xy_m = pose.sensor_xy_m;
    m.sensor_z_m = pose.sensor_z_m;
    m.heading_grid_rad = pose.heading_rad;
    m.pitch_rad = pose.pitch_rad;
    m.altitude_m = pose.altitude_m;
    m.slant_range_m = sonar_.max_range_m;
    m.port = p.port.samples;
    m.starboard = p.starboard.samples;
    if (options_.truth) {
      m.port_labels = p.port.truth_label;
      m.starboard_labels = p.starboard.truth_label;
    }
    mosaic_->add(m);
  }
  if (waterfall_)
    waterfall_->add_ping(p.port.samples, p.starboard.samples, sonar_.max_range_m, pose.altitude_m);
  if (truth_ && !p.port.truth_class.empty()) {
    truth_->add_ping(p.port.truth_class, p.starboard.truth_class, p.port.truth_label,
                     p.starboard.truth_label, p.port.truth_grazing_rad,
                     p.starboard.truth_grazing_rad);
  }
}

void SurveyProducts::end_line(std::size_t line) {
  const std::string name = line < names_.size() ? names_[line] : "line" + std::to_string(line + 1);
  if (waterfall_ && waterfall_->rows() > 0) {
    const auto path = dir_ / (name + "_waterfall.png");
    waterfall_->write(path.string());
    files_.push_back(path);
    if (waterfall_->pings_per_row() > 1) {
      notes_.push_back(path.filename().string() + ": " + std::to_string(waterfall_->rows()) +
                       " pings decimated along track, each row the mean of " +
                       std::to_string(waterfall_->pings_per_row()) + " pings (image limit " +
                       std::to_string(options_.waterfall_max_pixels) + " pixels)");
    }
  }
  if (truth_ && truth_->rows() > 0) {
    const auto path = dir_ / (name + "_truth.tif");
    truth_->write(path.string(), false, options_.write_options.metadata);
    files_.push_back(path);
  }
  waterfall_.reset();
  truth_.reset();
}

void SurveyProducts::abort() noexcept {
  waterfall_.reset();
  truth_.reset();
  mosaic_.reset();
}

void SurveyProducts::finish() {
  if (!mosaic_) return;
  const auto t0 = std::chrono::steady_clock::now();
  MosaicWriteOptions w = options_.write_options;
  w.rgb_path = (dir_ / "mosaic_rgb.tif").string();
  w.linear_full_scale = options_.display_linear_full_scale;
  if (options_.truth) w.labels_path = (dir_ / "truth_mosaic.tif").string();
  const auto path = dir_ / "mosaic.tif";
  write_mosaic(path.string(), scene_->frame, mosaic_->finish(), w);
  files_.push_back(path);
  files_.push_back(w.rgb_path);
  if (options_.truth) files_.push_back(w.labels_path);
  finish_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace sonarsynth
