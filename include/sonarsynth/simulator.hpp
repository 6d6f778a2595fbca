// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sonarsynth/ping_sink.hpp"
#include "sonarsynth/rendered_ping.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/simulation_config.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth {

struct AlongTrackPlanes;  // lib/private
struct SideParams;        // lib/private

/// Pilot pings for the automatic plane count: `count` pings spread evenly over the survey.
std::vector<PingPose> pilot_poses(const Survey& survey, const HeightGrid& seabed,
                                  std::size_t count = 16);

/// Without a survey: `count` poses stratified over the grid kept `margin_m` (the sonar's range)
/// inside its edges where it is large enough (one per cell of a square layout, deterministic
/// jitter, holes skipped), deterministic random headings, `altitude_m` above the seabed.
std::vector<PingPose> pilot_poses(const HeightGrid& seabed, double altitude_m, double margin_m,
                                  std::size_t count = 16);

/// How the along-track plane count was chosen.
struct AlongTrackChoice {
  int planes = 1;
  bool automatic = false;
  /// Automatic only: RMS dB difference per lit bin between the chosen count and the next one
  /// over the pilot pings (an estimate of the chosen count's error; for the largest count, the
  /// difference between the two largest); NaN otherwise.
  double estimated_error_db = std::numeric_limits<double>::quiet_NaN();
  /// Automatic only: the estimate of each count tried (1, 3, 5, ... against the next).
  std::vector<double> estimates_db;
  /// Automatic only: the count chosen with the objects' sections in the pilot pings (the count
  /// `planes` is chosen without them, for the seabed). When it is larger, a ping side whose
  /// profiles cut an object renders it over the range window the objects and their shadows
  /// affect, and `planes` elsewhere (docs/physics.md §1.3). Equal to `planes` otherwise.
  int object_planes = 1;
  /// Automatic only: the estimate of object_planes (as estimated_error_db, objects included);
  /// NaN when the scene has no objects or the count is not automatic.
  double object_estimated_error_db = std::numeric_limits<double>::quiet_NaN();
  std::size_t pilot_pings = 0;  ///< pilot pings that had lit bins
  double pilot_s = 0.0;         ///< wall time of the choice, seconds
};

/// Cumulative time split of the renderer, seconds summed over threads.
struct RenderTimings {
  double profile_s = 0.0;
  double render_s = 0.0;  ///< horizon sweep, clipping, integration
  double noise_s = 0.0;   ///< noise, TVG, quantisation
  /// Ping sides given finer planes for a small object (render.quality.small_object_planes),
  /// and the planes rendered on them.
  std::uint64_t refined_sides = 0;
  std::uint64_t refined_planes = 0;
  /// Ping sides whose object window was rendered with the object planes
  /// (AlongTrackChoice::object_planes), and the samples of those windows.
  std::uint64_t window_sides = 0;
  std::uint64_t window_samples = 0;
};

/// The caller's buffers that Simulator::render_batch fills: arrays of shape (pings, 2, samples)
/// in C order (ping, side 0 = port / 1 = starboard, sample NEAR -> FAR; samples =
/// SonarConfig::samples_per_channel), the fields of SideOutput. `samples` is required,
/// `clean_samples` exactly when SimulationConfig::clean_samples is on, the five truth arrays
/// exactly when SimulationConfig::truth is on; `saturated` and `invalid` (shape (pings, 2)) may
/// be null.
struct BatchOutput {
  float* samples = nullptr;
  float* clean_samples = nullptr;
  SampleClass* truth_class = nullptr;
  std::int32_t* object_id = nullptr;  ///< SideOutput::truth_label
  float* grazing_rad = nullptr;
  double* ground_x_m = nullptr;
  double* ground_y_m = nullptr;
  std::uint32_t* saturated = nullptr;
  std::uint32_t* invalid = nullptr;
};

/// Renders pings of a survey over a scene. Construction derives the global calibration
/// (absorption, gain, noise level) once; render_ping() is then a pure function of the pose and
/// its noise key (PingPose::ping_index).
class Simulator {
 public:
  /// Shares ownership of `scene` (not null): the Simulator keeps it alive. `reference_altitude_m`
  /// (metres, > 0) is the altitude of the global calibration (docs/physics.md §1.2). `pilot` =
  /// poses for the automatic along-track plane count (pilot_poses(survey, ...) for a survey);
  /// empty = pilot_poses(scene.bathymetry, reference_altitude_m, max range).
  Simulator(std::shared_ptr<const Scene> scene, const SimulationConfig& config,
            double reference_altitude_m, const std::vector<PingPose>& pilot = {});
  /// Convenience: copies `scene` into a Simulator-owned one (nothing is borrowed).
  Simulator(const Scene& scene, const SimulationConfig& config, double reference_altitude_m,
            const std::vector<PingPose>& pilot = {});
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// Renders one ping (thread-safe: each thread passes its own workspace).
  struct Workspace;
  struct WorkspaceDeleter {
    void operator()(Workspace* ws) const;
  };
  using WorkspacePtr = std::unique_ptr<Workspace, WorkspaceDeleter>;
  WorkspacePtr make_workspace() const;
  /// Renders one ping at `pose`: noisy samples, truth (SimulationConfig::truth) and noise-free
  /// samples (SimulationConfig::clean_samples) in one call. An unset pose.ping_index is given the
  /// next automatic noise key (see PingPose), stored in out.pose.ping_index.
  void render_ping(const PingPose& pose, Workspace& ws, RenderedPing& out,
                   RenderTimings* timings = nullptr) const;

  /// Renders `count` poses into `out` on `threads` threads (0: config().threads; 0 there: the
  /// hardware's), pose i = pose_at(i) (called from several threads: it must be thread-safe).
  /// Every pose is checked first (check_pose, and its noise key PingPose::ping_index must be
  /// set), so a bad pose throws InputError naming "<who>[i]" before anything is rendered. Each
  /// ping is a pure function of its pose and noise key: the output does not depend on the
  /// thread count nor on how the poses are split into batches (equal, bit for bit, to
  /// render_ping of each pose). The pings are rendered straight into `out` (no copy), and the
  /// threads' workspaces are kept for the next call (one per thread of the largest call).
  void render_batch(std::size_t count, const std::function<PingPose(std::size_t)>& pose_at,
                    const BatchOutput& out, unsigned threads = 0,
                    const std::string& who = "poses") const;
  /// As above, over a list of poses.
  void render_batch(const std::vector<PingPose>& poses, const BatchOutput& out,
                    unsigned threads = 0, const std::string& who = "poses") const;

  /// Renders every ping of `survey` on `config.threads` threads and hands them to `sink` in
  /// order, with the lifecycle documented on PingSink (begin ... finish, or abort on an
  /// exception, which is then rethrown). `progress(done, total)` is called from the calling
  /// thread after each block.
  RenderTimings run(const Survey& survey, PingSink& sink,
                    const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const;

  double absorption_db_per_m() const { return alpha_db_per_m_; }
  double gain_db() const;
  double thermal_noise_power() const { return noise_power_; }
  const SimulationConfig& config() const { return config_; }
  const Scene& scene() const { return *scene_; }
  const std::shared_ptr<const Scene>& shared_scene() const { return scene_; }
  const AlongTrackChoice& along_track() const { return along_track_; }
  /// The per-side renderer parameters derived from the configuration (for the benchmarks and
  /// tests of the build tree; the type is not part of the installed API).
  const SideParams& side_params() const;

 private:
  RenderTimings run_pings(const Survey& survey, PingSink& sink,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress) const;
  /// Where one side's output goes: arrays of SonarConfig::samples_per_channel values, the
  /// fields of SideOutput (clean_samples null unless SimulationConfig::clean_samples, the truth
  /// null unless SimulationConfig::truth). render_ping points them into its SideOutput,
  /// render_batch into the caller's slots (no copy).
  struct SideSpans {
    float* samples = nullptr;
    float* clean_samples = nullptr;
    SampleClass* truth_class = nullptr;
    std::int32_t* truth_label = nullptr;
    float* truth_grazing_rad = nullptr;
    /// The ground positions as SideOutput keeps them (render_ping): ranges and the side's
    /// geometry ...
    float* truth_ground_range_m = nullptr;
    Eigen::Vector2d* truth_nadir_xy_m = nullptr;
    Eigen::Vector2d* truth_across_dir = nullptr;
    /// ... or the positions themselves (render_batch), from the same float ranges.
    double* truth_ground_x_m = nullptr;
    double* truth_ground_y_m = nullptr;
    std::uint32_t* saturated = nullptr;
    std::uint32_t* invalid = nullptr;
  };
  /// Sizes `s`'s vectors for the configuration and points spans at them.
  SideSpans spans_of(SideOutput& s) const;
  /// Samples per side of the renderer (SonarConfig::samples_per_channel).
  std::size_t side_samples() const;
  /// Renders both sides of the ping at `pose` with noise key `key` into `port` and `starboard`.
  void render_sides(const PingPose& pose, std::uint64_t key, Workspace& ws, const SideSpans& port,
                    const SideSpans& starboard, RenderTimings* timings) const;
  /// `scale` multiplies the noise-free intensities before the noise (OutputScaling::normalise).
  void render_side_output(const PingPose& pose, std::uint64_t noise_key, bool starboard,
                          Workspace& ws, const SideSpans& out, RenderTimings* timings,
                          double scale = 1.0) const;
  /// max_value / (largest noise-free sample after TVG and gain over both sides of the ping), or
  /// 1 for a ping without echo: the factor of OutputScaling::Normalise::per_ping_max.
  double per_ping_max_scale(const PingPose& pose, Workspace& ws) const;
  /// TVG x gain (unless `scaled`), clamping and rounding of ws.accum into `out`; counts
  /// saturated and non-finite samples.
  void quantise(const Workspace& ws, bool scaled, float* out, std::uint32_t& saturated,
                std::uint32_t& invalid) const;
  /// Sums the planes' noise-free intensities of one side into ws.accum; the echo is left
  /// holding the central plane (rendered last, with truth if `truth`). With `refine`, a side
  /// that sees an object narrower than the planes' spacing gets finer planes there
  /// (ObjectPlaneRefiner, render.quality.small_object_planes).
  struct SideGeometry {
    Eigen::Vector2d nadir_xy_m, central_dir;
  };
  SideGeometry render_planes(const PingPose& pose, bool starboard,
                             const AlongTrackPlanes& run_planes, bool refine, bool truth,
                             Workspace& ws, RenderTimings* timings) const;
  /// The frozen speckle of one side (NoiseConfig::Model::kSpeckle) over ws.accum: the ground
  /// cell keys and texture shapes from the central plane's truth, the along-track field, the
  /// detector (sensor_effects.hpp); ws.noise_keys holds the ping's sample keys.
  void add_speckle(const PingPose& pose, bool starboard, const SideGeometry& geo, Workspace& ws,
                   double scale) const;
  /// Copies the central plane's truth (ws.echo) into `out`.
  void copy_truth(const Workspace& ws, const SideGeometry& geo, const SideSpans& out) const;
  AlongTrackChoice choose_along_track_planes(const std::vector<PingPose>& pilot) const;
  /// The object plane (index into Calibration::object_planes) at the azimuth of a single run
  /// plane, whose window is that plane's ws.accum scaled to its share of beta_eff in
  /// render_object_window (the intensity is linear in it: equal to round-off); the object plane
  /// count if none.
  std::size_t shared_plane(const AlongTrackPlanes& run_planes) const;
  /// Replaces ws.accum over the samples that slant ranges [r_lo_m, r_hi_m] may reach by the sum
  /// of the object planes, rendered from ws.object_profiles over those samples only.
  void render_object_window(double r_lo_m, double r_hi_m, Workspace& ws,
                            RenderTimings* timings) const;
  /// Truth of a refined side: object energy per sample over the planes, the brightest object
  /// contributor's truth, and the central plane's truth overridden where objects hold more than
  /// half of the sample's energy.
  void begin_object_truth(Workspace& ws) const;
  void collect_object_truth(Workspace& ws) const;
  void apply_object_truth(Workspace& ws) const;

  std::shared_ptr<const Scene> scene_;
  /// Workspaces render_batch lends its threads, kept from call to call with their buffers
  /// grown (a fresh one costs its first pings their allocations and page faults).
  mutable std::mutex spare_mutex_;
  mutable std::vector<WorkspacePtr> spare_workspaces_;
  /// Automatic noise keys handed out so far (PingPose::ping_index unset).
  mutable std::atomic<std::uint64_t> automatic_keys_{0};
  SimulationConfig config_;
  /// The renderer's per-run state derived from the configuration (lib/private).
  struct Calibration;
  std::unique_ptr<Calibration> cal_;
  double alpha_db_per_m_ = 0.0;
  double noise_power_ = 0.0;
  double paper_sigma_out_ = 0.0;  // Rayleigh sigma of the paper noise, output units
  AlongTrackChoice along_track_;
};

}  // namespace sonarsynth
