// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/survey_products.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <span>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/geo_truth.hpp"
#include "sonarsynth/formats/products/row_spool.hpp"
#include "sonarsynth/formats/products/sink_threads.hpp"
#include "sonarsynth/formats/products/survey_mosaic.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"

namespace sonarsynth {

std::vector<std::string> product_option_flags(const SurveyProductOptions& o) {
  const SurveyProductOptions d;
  std::vector<std::string> flags;
  if (!o.mosaic) flags.emplace_back("--no-mosaic");
  if (!o.waterfalls) flags.emplace_back("--no-waterfall");
  if (!o.truth) flags.emplace_back("--no-truth");
  if (o.mosaic_pixel_m != d.mosaic_pixel_m) {
    // The shortest text that reads back as the same double.
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, o.mosaic_pixel_m);
    flags.push_back("--res " + std::string(text, r.ptr));
  }
  if (o.write_options.format != d.write_options.format) flags.emplace_back("--of GTiff");
  for (const auto& [key, value] : o.write_options.creation_options) {
    flags.push_back("--co " + key + "=" + value);
  }
  if (o.waterfall_max_pixels != d.waterfall_max_pixels) {
    flags.push_back("--waterfall-max-pixels " + std::to_string(o.waterfall_max_pixels));
  }
  return flags;
}

void SurveyProductOptions::validate() const {
  if (!(mosaic_pixel_m > 0.0) || !std::isfinite(mosaic_pixel_m)) {
    throw InputError("products: mosaic pixel = " + std::to_string(mosaic_pixel_m) +
                     " m. Violated constraint: pixel > 0");
  }
  mosaic_options.validate();
  if (mosaic) write_options.validate();  // creation options: refused before any rendering
}

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
            const SurveyProductOptions& options, const GeoFrame& frame)
      : LinePart(std::move(dir), std::move(names), options.background_images),
        options_(options),
        frame_(frame) {}
  void begin_line(std::size_t /*line*/) override {
    truth_ = std::make_shared<TruthWaterfall>(dir());
    gcps_ = {};
    gcps_.epsg = frame_.epsg();
  }
  void ping(const RenderedPing& p) override {
    if (truth_ && !p.port.truth_class.empty()) {
      if (truth_->rows() % kGcpPingStep == 0) add_gcps(p, truth_->rows());
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
    t->set_ground_control(thinned_gcps());
    t->set_grazing(options_.truth_grazing);
    t->set_cog_layout(options_.write_options.format == MosaicRasterFormat::cog);
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

  // Ground control points of the line rasters (docs/labels.md): the truth's ground position of
  // kGcpSamples samples a side, spread over the samples that have one, every kGcpPingStep pings;
  // thinned to at most kGcpRows rows when the line is written.
  static constexpr std::size_t kGcpPingStep = 16;
  static constexpr std::size_t kGcpSamples = 8;
  static constexpr std::size_t kGcpRows = 32;
  void add_gcps(const RenderedPing& p, std::size_t row) {
    for (const bool starboard : {false, true}) {
      const SideOutput& s = starboard ? p.starboard : p.port;
      std::vector<std::size_t> placed;
      for (std::size_t i = 0; i < s.truth_ground_range_m.size(); ++i) {
        if (s.truth_ground_xy(i).allFinite()) placed.push_back(i);
      }
      if (placed.empty()) continue;
      for (std::size_t k = 0; k < kGcpSamples; ++k) {
        const std::size_t i = placed[k * (placed.size() - 1) / (kGcpSamples - 1)];
        const Eigen::Vector2d en = frame_.projected_from_local(s.truth_ground_xy(i));
        gcps_.points.push_back({row, starboard, i, en.x(), en.y()});
      }
    }
  }
  WaterfallGroundControl thinned_gcps() const {
    std::vector<std::size_t> rows;
    for (const auto& g : gcps_.points) {
      if (rows.empty() || rows.back() != g.row) rows.push_back(g.row);
    }
    const std::size_t step = (rows.size() + kGcpRows - 1) / kGcpRows;
    WaterfallGroundControl out;
    out.epsg = gcps_.epsg;
    for (const auto& g : gcps_.points) {
      const auto k = static_cast<std::size_t>(std::lower_bound(rows.begin(), rows.end(), g.row) -
                                              rows.begin());
      if (step <= 1 || k % step == 0 || k + 1 == rows.size()) out.points.push_back(g);
    }
    return out;
  }

  const SurveyProductOptions& options_;
  GeoFrame frame_;
  std::shared_ptr<TruthWaterfall> truth_;
  WaterfallGroundControl gcps_;
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
    mosaic_ = detail::make_survey_mosaic(dir, shared_scene, sonar, lines, options_);
  }
  if (options_.waterfalls) {
    waterfall_ = std::make_unique<WaterfallPart>(dir, names, options_, sonar);
  }
  if (options_.truth) {
    truth_ = std::make_unique<TruthPart>(dir, names, options_, shared_scene->frame);
  }
  if (options_.truth) {
    vectors_ = std::make_unique<geo_truth::GeoTruthWriter>(dir, shared_scene, names,
                                                           options_.write_options.overwrite);
  }
}

SurveyProducts::~SurveyProducts() = default;

std::vector<std::pair<std::string, PingSink*>> SurveyProducts::parts() {
  std::vector<std::pair<std::string, PingSink*>> p;
  if (mosaic_) p.emplace_back("mosaic", mosaic_.get());
  if (waterfall_) p.emplace_back("waterfall", waterfall_.get());
  if (truth_) p.emplace_back("truth", truth_.get());
  if (vectors_) p.emplace_back("vectors", vectors_.get());
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
  if (vectors_) out.insert(out.end(), vectors_->files().begin(), vectors_->files().end());
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
