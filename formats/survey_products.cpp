// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/survey_products.hpp"

#include <chrono>
#include <cmath>
#include <functional>
#include <span>
#include <tuple>
#include <utility>

#include "sink_threads.hpp"
#include "sonarsynth/error.hpp"
#include "truth_labels.hpp"

namespace sonarsynth {

void SurveyProductOptions::validate() const {
  if (!(mosaic_pixel_m > 0.0) || !std::isfinite(mosaic_pixel_m)) {
    throw InputError("products: mosaic pixel = " + std::to_string(mosaic_pixel_m) +
                     " m. Violated constraint: pixel > 0");
  }
  mosaic_options.validate();
  if (mosaic) write_options.validate();  // creation options: refused before any rendering
}

/// The survey mosaic: every ping gridded as it comes, the files written by finish().
class SurveyProducts::MosaicPart final : public PingSink {
 public:
  MosaicPart(std::filesystem::path dir, std::shared_ptr<const Scene> scene,
             const SonarConfig& sonar, const std::vector<SurveyLine>& lines,
             const SurveyProductOptions& options)
      : dir_(std::move(dir)), scene_(std::move(scene)), sonar_(sonar), options_(options) {
    Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    for (const SurveyLine& l : lines) {
      for (const Eigen::Vector2d& p : l.waypoints_xy_m) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    // The swath reaches at most the slant range to either side; clip to the bathymetry.
    const Eigen::Vector4d bb = scene_->bathymetry.bounds();
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(sonar.max_range_m);
    lo = (lo - r).cwiseMax(Eigen::Vector2d(bb[0], bb[1]));
    hi = (hi + r).cwiseMin(Eigen::Vector2d(bb[2], bb[3]));
    if (!(lo.x() < hi.x() && lo.y() < hi.y())) {
      throw InputError("products: the survey lines do not overlap the bathymetry grid");
    }
    if (options_.truth) {
      std::vector<std::int32_t> ids;
      for (const ObjectPrimitive& o : scene_->objects.primitives()) ids.push_back(o.id);
      codes_ = std::make_unique<labels::MosaicLabelCodes>(std::move(ids));
    }
    grid_ =
        std::make_unique<MosaicGrid>(MosaicGrid::geometry_covering(lo, hi, options_.mosaic_pixel_m),
                                     options_.mosaic_options, &scene_->bathymetry);
    if (options_.mosaic_resident_bytes > 0) grid_->spill_to(dir_, options_.mosaic_resident_bytes);
  }

  void begin_line(std::size_t /*line*/) override {
    if (grid_) grid_->break_line();
  }

  void ping(const RenderedPing& p) override {
    if (!grid_) return;
    const PingPose& pose = p.pose;
    MosaicPing m;
    m.sensor_xy_m = pose.sensor_xy_m;
    m.sensor_z_m = pose.sensor_z_m;
    m.heading_grid_rad = pose.heading_rad;
    m.pitch_rad = pose.pitch_rad;
    m.altitude_m = pose.altitude_m;
    m.slant_range_m = sonar_.max_range_m;
    m.port = p.port.samples;
    m.starboard = p.starboard.samples;
    if (codes_ && !p.port.truth_class.empty()) {
      // Class, id and shadow caster in one gridded code (formats/truth_labels.hpp).
      codes_->encode(p.port.truth_class, p.port.truth_label, port_codes_);
      codes_->encode(p.starboard.truth_class, p.starboard.truth_label, stbd_codes_);
      m.port_labels = port_codes_;
      m.starboard_labels = stbd_codes_;
    }
    grid_->add(m);
  }

  void finish() override {
    if (!grid_) return;
    const auto t0 = std::chrono::steady_clock::now();
    // The grid has gridded every ping: it does not read the bathymetry again.
    if (options_.after_last_bathymetry_use) options_.after_last_bathymetry_use();
    MosaicWriteOptions w = options_.write_options;
    w.rgb_path = (dir_ / "mosaic_rgb.tif").string();
    w.linear_full_scale = options_.display_linear_full_scale;
    if (options_.display_window_db) {
      w.fixed_db = true;
      std::tie(w.lo_db, w.hi_db) = *options_.display_window_db;
    }
    if (options_.truth) w.labels_path = (dir_ / "truth_mosaic.tif").string();
    const auto path = dir_ / "mosaic.tif";
    // The files are written window by window from the tiles (no image in memory): the tiles
    // in memory are reduced to their final values first, and released with the grid after.
    grid_->finalize();
    detail::release_free_memory();
    std::vector<std::filesystem::path> label_files;
    if (codes_ && grid_->has_labels()) {
      label_files = {dir_ / "truth_mosaic_class.tif", dir_ / "truth_mosaic_instance.tif"};
      labels::write_mosaic_label_rasters(label_files[0].string(), label_files[1].string(),
                                         scene_->frame, *grid_, *codes_, w.overwrite, w.metadata);
    }
    std::function<void(std::span<std::int32_t>)> label_map;
    if (codes_) label_map = [this](std::span<std::int32_t> c) { codes_->decode_labels(c); };
    write_mosaic(path.string(), scene_->frame, *grid_, w, label_map);
    grid_.reset();
    detail::release_free_memory();
    files_ = {path, w.rgb_path};
    if (options_.truth) files_.push_back(w.labels_path);
    files_.insert(files_.end(), label_files.begin(), label_files.end());
    finish_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void abort() noexcept override { grid_.reset(); }

  const std::vector<std::filesystem::path>& files() const { return files_; }
  double finish_s() const { return finish_s_; }

 private:
  std::filesystem::path dir_;
  std::shared_ptr<const Scene> scene_;
  SonarConfig sonar_;
  const SurveyProductOptions& options_;
  std::unique_ptr<MosaicGrid> grid_;
  std::unique_ptr<labels::MosaicLabelCodes> codes_;
  std::vector<std::int32_t> port_codes_, stbd_codes_;
  std::vector<std::filesystem::path> files_;
  double finish_s_ = 0.0;
};

/// A product of one image per line: accumulated while the line renders, written on a background
/// thread while the next line accumulates.
class SurveyProducts::LinePart : public PingSink {
 public:
  LinePart(std::filesystem::path dir, std::vector<std::string> names, bool background)
      : dir_(std::move(dir)), names_(std::move(names)), background_(background) {}

  void end_line(std::size_t line) final {
    job_.wait();  // the previous line's image, before the slots may move
    if (files_.size() <= line) {
      files_.resize(line + 1);
      notes_.resize(line + 1);
    }
    const std::string name =
        line < names_.size() ? names_[line] : "line" + std::to_string(line + 1);
    std::function<void()> job = take_line(name, files_[line], notes_[line]);
    if (!job) return;
    if (background_) {
      job_.run(std::move(job));
    } else {
      const double cpu0 = detail::thread_cpu_s();
      job();
      inline_cpu_s_ += detail::thread_cpu_s() - cpu0;
    }
  }
  void finish() final { job_.wait(); }
  void abort() noexcept final {
    try {
      job_.wait();
    } catch (...) {  // the run is abandoned: the files are discarded anyway
    }
    drop();
  }

  /// The paths written for `line` (none: empty), and its note (empty: none).
  const std::vector<std::vector<std::filesystem::path>>& files() const { return files_; }
  const std::vector<std::string>& notes() const { return notes_; }
  double cpu_s() const { return job_.cpu_s() + inline_cpu_s_; }

 protected:
  /// The line's accumulator handed over as a job that writes `<dir>/<name><suffix>` files and
  /// sets `files` (and `note` if there is one), or an empty job if the line has nothing to write.
  virtual std::function<void()> take_line(const std::string& name,
                                          std::vector<std::filesystem::path>& files,
                                          std::string& note) = 0;
  virtual void drop() noexcept = 0;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  std::vector<std::vector<std::filesystem::path>> files_;
  std::vector<std::string> notes_;
  bool background_;
  double inline_cpu_s_ = 0.0;  ///< of the jobs run on the calling thread
  detail::BackgroundJob job_;
};

class SurveyProducts::WaterfallPart final : public LinePart {
 public:
  WaterfallPart(std::filesystem::path dir, std::vector<std::string> names,
                const SurveyProductOptions& options, const SonarConfig& sonar)
      : LinePart(std::move(dir), std::move(names), options.background_images),
        options_(options),
        sonar_(sonar) {}
  void begin_line(std::size_t /*line*/) override {
    // Rows are spooled next to the outputs (the same file system; the spool files are unnamed).
    WaterfallOptions wo;
    wo.spool_dir = dir();
    wo.max_pixels = options_.waterfall_max_pixels;
    wo.linear_full_scale = options_.display_linear_full_scale;
    if (options_.display_window_db) {
      wo.fixed_db = true;
      std::tie(wo.lo_db, wo.hi_db) = *options_.display_window_db;
    }
    wo.metadata = options_.write_options.metadata;  // the run's items, in every product
    waterfall_ = std::make_shared<Waterfall>(wo);
  }
  void ping(const RenderedPing& p) override {
    if (waterfall_) {
      waterfall_->add_ping(p.port.samples, p.starboard.samples, sonar_.max_range_m,
                           p.pose.altitude_m);
    }
  }

 private:
  std::function<void()> take_line(const std::string& name,
                                  std::vector<std::filesystem::path>& files,
                                  std::string& note) override {
    std::shared_ptr<Waterfall> w = std::move(waterfall_);
    if (!w || w->rows() == 0) return {};
    const std::size_t max_pixels = options_.waterfall_max_pixels;
    Waterfall::RowTap tap = options_.waterfall_rows ? options_.waterfall_rows(name) : nullptr;
    return [w, path = dir() / (name + "_waterfall.png"), max_pixels, &files, &note, tap] {
      w->write(path.string(), tap);
      files = {path};
      if (w->pings_per_row() > 1) {
        note = path.filename().string() + ": " + std::to_string(w->rows()) +
               " pings decimated along track, each row the mean of " +
               std::to_string(w->pings_per_row()) + " pings (image limit " +
               std::to_string(max_pixels) + " pixels)";
      }
    };
  }
  void drop() noexcept override { waterfall_.reset(); }

  const SurveyProductOptions& options_;
  SonarConfig sonar_;
  std::shared_ptr<Waterfall> waterfall_;
};

class SurveyProducts::TruthPart final : public LinePart {
 public:
  TruthPart(std::filesystem::path dir, std::vector<std::string> names,
            const SurveyProductOptions& options)
      : LinePart(std::move(dir), std::move(names), options.background_images), options_(options) {}
  void begin_line(std::size_t /*line*/) override {
    truth_ = std::make_shared<TruthWaterfall>(dir());
  }
  void ping(const RenderedPing& p) override {
    if (truth_ && !p.port.truth_class.empty()) {
      truth_->add_ping(p.port.truth_class, p.starboard.truth_class, p.port.truth_label,
                       p.starboard.truth_label, p.port.truth_grazing_rad,
                       p.starboard.truth_grazing_rad);
    }
  }

 private:
  std::function<void()> take_line(const std::string& name,
                                  std::vector<std::filesystem::path>& files,
                                  std::string& /*note*/) override {
    std::shared_ptr<TruthWaterfall> t = std::move(truth_);
    if (!t || t->rows() == 0) return {};
    // The label rasters (docs/labels.md) next to the truth of the line, from the same spool rows.
    TruthWaterfall::LabelRowTap tap = options_.label_rows ? options_.label_rows(name) : nullptr;
    return
        [t, path = dir() / (name + "_truth.tif"), class_path = dir() / (name + "_truth_class.tif"),
         instance_path = dir() / (name + "_truth_instance.tif"), this, &files, tap] {
          t->write_with_labels(path.string(), class_path.string(), instance_path.string(), false,
                               options_.write_options.metadata, tap);
          files = {path, class_path, instance_path};
        };
  }
  void drop() noexcept override { truth_.reset(); }

  const SurveyProductOptions& options_;
  std::shared_ptr<TruthWaterfall> truth_;
};

SurveyProducts::SurveyProducts(std::filesystem::path dir, std::shared_ptr<const Scene> shared_scene,
                               const SonarConfig& sonar, const std::vector<SurveyLine>& lines,
                               SurveyProductOptions options)
    : options_(std::move(options)) {
  if (!shared_scene) throw InputError("products: scene = null. Violated constraint: a scene");
  options_.validate();
  // One ping must fit in a waterfall row: checked before anything is rendered.
  if (options_.waterfalls && 2 * sonar.samples_per_channel > options_.waterfall_max_pixels) {
    throw InputError(
        "products: waterfall max pixels = " + std::to_string(options_.waterfall_max_pixels) +
        ". Violated constraint: at least one row of 2 x samples = " +
        std::to_string(2 * sonar.samples_per_channel) + " pixels");
  }
  std::vector<std::string> names;
  for (const SurveyLine& l : lines) names.push_back(l.name);
  if (options_.mosaic) {
    mosaic_ = std::make_unique<MosaicPart>(dir, shared_scene, sonar, lines, options_);
  }
  if (options_.waterfalls) {
    waterfall_ = std::make_unique<WaterfallPart>(dir, names, options_, sonar);
  }
  if (options_.truth) truth_ = std::make_unique<TruthPart>(dir, names, options_);
}

SurveyProducts::~SurveyProducts() = default;

std::vector<std::pair<std::string, PingSink*>> SurveyProducts::parts() {
  std::vector<std::pair<std::string, PingSink*>> p;
  if (mosaic_) p.emplace_back("mosaic", mosaic_.get());
  if (waterfall_) p.emplace_back("waterfall", waterfall_.get());
  if (truth_) p.emplace_back("truth", truth_.get());
  return p;
}

void SurveyProducts::begin(const RunDescription& run) {
  for (auto& [name, part] : parts()) part->begin(run);
}

void SurveyProducts::begin_line(std::size_t line) {
  for (auto& [name, part] : parts()) part->begin_line(line);
}

void SurveyProducts::ping(const RenderedPing& p) {
  for (auto& [name, part] : parts()) part->ping(p);
}

void SurveyProducts::end_line(std::size_t line) {
  for (auto& [name, part] : parts()) part->end_line(line);
}

void SurveyProducts::finish() {
  for (auto& [name, part] : parts()) part->finish();
}

void SurveyProducts::abort() noexcept {
  for (auto& [name, part] : parts()) part->abort();
}

double SurveyProducts::finish_s() const {
  return mosaic_ ? mosaic_->finish_s() : 0.0;
}

std::vector<std::pair<std::string, double>> SurveyProducts::writer_cpu_s() const {
  std::vector<std::pair<std::string, double>> out;
  if (waterfall_) out.emplace_back("waterfall images", waterfall_->cpu_s());
  if (truth_) out.emplace_back("truth images", truth_->cpu_s());
  return out;
}

std::vector<std::filesystem::path> SurveyProducts::files() const {
  std::vector<std::filesystem::path> out;
  const std::size_t lines =
      std::max(waterfall_ ? waterfall_->files().size() : 0, truth_ ? truth_->files().size() : 0);
  for (std::size_t l = 0; l < lines; ++l) {
    for (const LinePart* part : {waterfall_.get(), truth_.get()}) {
      if (part && l < part->files().size()) {
        out.insert(out.end(), part->files()[l].begin(), part->files()[l].end());
      }
    }
  }
  if (mosaic_) out.insert(out.end(), mosaic_->files().begin(), mosaic_->files().end());
  return out;
}

std::vector<std::string> SurveyProducts::notes() const {
  std::vector<std::string> out;
  if (waterfall_) {
    for (const std::string& n : waterfall_->notes()) {
      if (!n.empty()) out.push_back(n);
    }
  }
  return out;
}

}  // namespace sonarsynth
