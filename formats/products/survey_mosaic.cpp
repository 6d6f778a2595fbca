// SPDX-License-Identifier: MIT
// The survey mosaic of `simulate`: every ping gridded as it comes (or spooled for the gain
// normalisation), the mosaic files written at the end.
#include "sonarsynth/formats/products/survey_mosaic.hpp"

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
namespace {

/// The survey mosaic: every ping gridded as it comes, the files written by finish().
class MosaicPart final : public detail::SurveyMosaic {
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
    if (options_.gain_normalisation != GainNormalisation::kOff) {
      gain_ = std::make_unique<GainNormaliser>(options_.gain_normalisation);
    }
  }

  void begin_line(std::size_t /*line*/) override {
    if (gain_) {
      break_before_ = true;
    } else if (grid_) {
      grid_->break_line();
    }
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
      // Class, id and shadow caster in one gridded code
      // (formats/private/sonarsynth/formats/products/truth_labels.hpp).
      codes_->encode(p.port.truth_class, p.port.truth_label, port_codes_);
      codes_->encode(p.starboard.truth_class, p.starboard.truth_label, stbd_codes_);
      m.port_labels = port_codes_;
      m.starboard_labels = stbd_codes_;
    }
    if (gain_) {
      spool_ping(m);
      return;
    }
    grid_->add(m);
  }

  /// Gain normalisation: the ping's statistics counted, the ping kept in the spool (its samples
  /// and label codes, the codes' bits as floats) for finish().
  void spool_ping(const MosaicPing& m) {
    gain_->add_ping(m.port, m.starboard, m.slant_range_m, m.altitude_m);
    // Band 2 (the label codes' bits) only when the run grids labels; a ping without codes in
    // such a run spools zeros there (SpooledPing::labels says not to read them).
    const std::size_t bands = codes_ ? 2 : 1;
    if (!spool_) spool_ = std::make_unique<detail::SideSpool>(dir_, bands, "mosaic spool");
    const auto as_floats = [](std::span<const std::int32_t> codes, std::size_t n,
                              std::vector<float>& out) {
      out.assign(codes.empty() ? n : codes.size(), 0.0f);
      if (!codes.empty()) std::memcpy(out.data(), codes.data(), codes.size() * sizeof(float));
    };
    as_floats(m.port_labels, m.port.size(), port_bits_);
    as_floats(m.starboard_labels, m.starboard.size(), stbd_bits_);
    const std::span<const float> port[2] = {m.port, port_bits_};
    const std::span<const float> stbd[2] = {m.starboard, stbd_bits_};
    spool_->append(std::span(port, bands), std::span(stbd, bands));
    SpooledPing s;
    s.ping = m;
    s.ping.port = {};
    s.ping.starboard = {};
    s.ping.port_labels = {};
    s.ping.starboard_labels = {};
    s.port_n = m.port.size();
    s.stbd_n = m.starboard.size();
    s.labels = !m.port_labels.empty() || !m.starboard_labels.empty();
    s.break_before = break_before_;
    break_before_ = false;
    spooled_.push_back(s);
  }

  /// What the spool does not hold of a ping (gain normalisation).
  struct SpooledPing {
    MosaicPing ping;  ///< without its spans
    std::size_t port_n = 0, stbd_n = 0;
    bool labels = false;
    bool break_before = false;  ///< a new line starts with this ping
  };

  /// One spooled ping read back and multiplied by its gains, ready to grid.
  struct PreparedPing {
    std::vector<float> port, stbd;
    std::vector<std::int32_t> port_codes, stbd_codes;
  };

  /// Reads the spooled pings back in order and applies the gains: on a thread of its own while
  /// the calling thread grids (the pings reach the grid in the same order as without it, so the
  /// mosaic is the same). At most kQueue pings wait; stop() (or the destructor) ends the thread.
  class SpoolReader {
   public:
    SpoolReader(const detail::SideSpool& spool, const std::vector<SpooledPing>& spooled,
                const GainNormaliser& gain)
        : spool_(spool), spooled_(spooled), gain_(gain), thread_([this] { run(); }) {}
    ~SpoolReader() { stop(); }
    SpoolReader(const SpoolReader&) = delete;
    SpoolReader& operator=(const SpoolReader&) = delete;
    /// The next ping (in spool order); rethrows what the reading thread threw.
    PreparedPing next() {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || error_ || done_; });
      if (queue_.empty()) {
        if (error_) std::rethrow_exception(error_);
        throw std::logic_error("mosaic spool: read past its last ping");
      }
      PreparedPing p = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      changed_.notify_all();
      return p;
    }
    void stop() noexcept {
      {
        std::lock_guard lock(mutex_);
        stopping_ = true;
      }
      changed_.notify_all();
      if (thread_.joinable()) thread_.join();
    }

   private:
    static constexpr std::size_t kQueue = 64;
    void run() noexcept {
      try {
        const float pads[2] = {std::numeric_limits<float>::quiet_NaN(), 0.0f};
        detail::SideSpool::Reader reader(spool_, std::span(pads, spool_.bands()));
        const std::size_t side = spool_.side();
        std::vector<float> row(spool_.bands() * spool_.cols());
        for (const SpooledPing& s : spooled_) {
          if (!reader.next(row)) throw FormatError("mosaic spool: the file ended early");
          // Image row: port FAR -> NEAR | starboard NEAR -> FAR, band by band.
          const float* values = row.data();
          const float* bits = row.data() + spool_.cols();
          PreparedPing p;
          p.port.resize(s.port_n);
          p.stbd.resize(s.stbd_n);
          p.port_codes.resize(s.labels ? s.port_n : 0);
          p.stbd_codes.resize(s.labels ? s.stbd_n : 0);
          for (std::size_t i = 0; i < s.port_n; ++i) {
            p.port[i] = values[side - 1 - i];
            if (s.labels) std::memcpy(&p.port_codes[i], &bits[side - 1 - i], sizeof(float));
          }
          for (std::size_t i = 0; i < s.stbd_n; ++i) {
            p.stbd[i] = values[side + i];
            if (s.labels) std::memcpy(&p.stbd_codes[i], &bits[side + i], sizeof(float));
          }
          gain_.apply(p.port, p.stbd, s.ping.slant_range_m, s.ping.altitude_m);
          std::unique_lock lock(mutex_);
          changed_.wait(lock, [&] { return stopping_ || queue_.size() < kQueue; });
          if (stopping_) return;
          queue_.push_back(std::move(p));
          lock.unlock();
          changed_.notify_all();
        }
      } catch (...) {
        std::lock_guard lock(mutex_);
        error_ = std::current_exception();
      }
      {
        std::lock_guard lock(mutex_);
        done_ = true;
      }
      changed_.notify_all();
    }

    const detail::SideSpool& spool_;
    const std::vector<SpooledPing>& spooled_;
    const GainNormaliser& gain_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<PreparedPing> queue_;
    bool stopping_ = false;
    bool done_ = false;
    std::exception_ptr error_;
    std::thread thread_;  ///< last: started when the rest is ready
  };

  /// Grids the spooled pings, each multiplied by the gains of the whole survey (read back and
  /// multiplied on a second thread while this one grids: the run's last seconds use both cores).
  void grid_spooled() {
    if (!gain_) return;
    gain_->finish();
    if (!spool_) return;
    {
      SpoolReader reader(*spool_, spooled_, *gain_);
      for (const SpooledPing& s : spooled_) {
        const PreparedPing p = reader.next();
        MosaicPing m = s.ping;
        m.port = p.port;
        m.starboard = p.stbd;
        m.port_labels = p.port_codes;
        m.starboard_labels = p.stbd_codes;
        if (s.break_before) grid_->break_line();
        grid_->add(m);
      }
    }
    spool_.reset();
    spooled_.clear();
    spooled_.shrink_to_fit();
  }

  void finish() override {
    if (!grid_) return;
    const auto t0 = std::chrono::steady_clock::now();
    grid_spooled();
    // The grid has gridded every ping: it does not read the bathymetry again.
    if (options_.after_last_bathymetry_use) options_.after_last_bathymetry_use();
    MosaicWriteOptions w = options_.write_options;
    // The processing (docs/scene-format.md, output.mosaic), recorded when it is not the raw
    // gridding (whose files stay as they were).
    const MosaicOptions& mo = options_.mosaic_options;
    if (mo.nadir_blank_m > 0.0 || options_.gain_normalisation != GainNormalisation::kOff) {
      std::ostringstream nadir;
      nadir << (mo.nadir_blank_m > 0.0 ? (mo.nadir_fill ? "fill" : "blank") : "raw");
      if (mo.nadir_blank_m > 0.0) {
        nadir << " (first return: " << mo.nadir_blank_m << " m of slant range not gridded)";
      }
      w.metadata.emplace_back("SONARSYNTH_MOSAIC_NADIR", nadir.str());
      w.metadata.emplace_back("SONARSYNTH_GAIN_NORMALISATION",
                              to_string(options_.gain_normalisation));
    }
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
                                         scene_->frame, *grid_, *codes_, w.overwrite, w.metadata,
                                         w.format == MosaicRasterFormat::cog);
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

  void abort() noexcept override {
    grid_.reset();
    spool_.reset();
  }

  const std::vector<std::filesystem::path>& files() const override { return files_; }
  double finish_s() const override { return finish_s_; }

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
  // Gain normalisation (options_.gain_normalisation): the statistics, the pings waiting in the
  // spool and what the spool does not hold of each.
  std::unique_ptr<GainNormaliser> gain_;
  std::unique_ptr<detail::SideSpool> spool_;
  std::vector<SpooledPing> spooled_;
  std::vector<float> port_bits_, stbd_bits_;
  bool break_before_ = false;
};

}  // namespace

namespace detail {

std::unique_ptr<SurveyMosaic> make_survey_mosaic(std::filesystem::path dir,
                                                 std::shared_ptr<const Scene> scene,
                                                 const SonarConfig& sonar,
                                                 const std::vector<SurveyLine>& lines,
                                                 const SurveyProductOptions& options) {
  return std::make_unique<MosaicPart>(std::move(dir), std::move(scene), sonar, lines, options);
}

}  // namespace detail
}  // namespace sonarsynth
