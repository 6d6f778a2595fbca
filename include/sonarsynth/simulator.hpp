// SPDX-License-Identifier: MIT
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "sonarsynth/absorption.hpp"
#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/sonar.hpp"
#include "sonarsynth/survey.hpp"
#include "sonarsynth/tvg.hpp"

namespace sonarsynth {

/// Which physics is on. Every switch that is off costs nothing in the inner loop.
struct PhysicsConfig {
  /// paper (default, reproduces Gwon et al.: per-ray R K Phi cos(theta), equal to Lambert with
  /// mu = R) or lambert (per-material mu).
  BackscatterModel backscatter = BackscatterModel::paper;
  bool shadows = true;
  bool spreading = true;     ///< two-way r^-4
  bool beam_pattern = true;  ///< vertical beam pattern (off: uniform)
  bool absorption = true;    ///< Francois-Garrison from sonar frequency and `water`
  Seawater water;
  double calibration_k = 1.0;  ///< global constant K, > 0 (never per ping)
};

/// Speed/accuracy knobs of the renderer.
struct QualityConfig {
  /// along_track_planes value that lets the Simulator choose the count (see below).
  static constexpr int kAutoPlanes = 0;
  ProfileOptions profile;
  int gauss_points = 2;  ///< [1, 5]
  /// K beam planes across the horizontal beam, [1, 64], or kAutoPlanes (the default): the fewest
  /// of 1, 3, 5, 9, 15 planes whose estimated along-track error, the RMS dB difference per lit
  /// bin against the next count over a few pilot pings, is at most along_track_tolerance_db. A
  /// smooth seabed gets one plane; one rough on the scale of the beam's along-track footprint
  /// gets as many as it needs.
  int along_track_planes = kAutoPlanes;
  double along_track_tolerance_db = 1.0;  ///< auto only, > 0
  void validate() const;

  /// The `--quality` presets, applied over the configured values (docs/scene-format.md):
  /// "fast" = 1 Gauss point, 8 object segments, 1 along-track plane; "default" changes nothing;
  /// "high" = 4 grid subdivisions, 3 Gauss points, automatic along-track planes with a 0.25 dB
  /// tolerance. Returns false (and changes nothing) for any other name.
  bool apply_preset(std::string_view name) {
    if (name == "fast") {
      gauss_points = 1;
      profile.object_segments = 8;
      along_track_planes = 1;
    } else if (name == "high") {
      profile.grid_subdivisions = 4;
      gauss_points = 3;
      along_track_planes = kAutoPlanes;
      along_track_tolerance_db = 0.25;
    } else if (name != "default") {
      return false;
    }
    return true;
  }
  /// "fast, default or high".
  static constexpr const char* kPresetNames = "fast, default or high";
};

/// K along-track beam planes: azimuths from the across-track direction, evenly across +-1.25
/// horizontal beam widths (0 for K = 1), and their shares of `beta_eff_rad`, weighted by the
/// two-way horizontal pattern and summing to it exactly.
struct AlongTrackPlanes {
  std::vector<double> azimuth_rad;
  std::vector<double> beta_eff_rad;
  std::size_t size() const { return azimuth_rad.size(); }
};
AlongTrackPlanes make_along_track_planes(const SonarConfig& sonar, int count, double beta_eff_rad);

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
  std::size_t pilot_pings = 0;  ///< pilot pings that had lit bins
  double pilot_s = 0.0;         ///< wall time of the choice, seconds
};

struct NoiseConfig {
  enum class Model {
    kNone,     ///< noise-free intensities
    kPaper,    ///< Gwon eq. (2): I(1 + u) + r
    kSpeckle,  ///< complex Gaussian speckle (+ K texture per material) + thermal noise
  };
  Model model = Model::kSpeckle;
  double paper_uniform_half_width = 0.3;  ///< a of eq. (2), [0, 1]
  /// Signal-to-noise ratio, dB. Speckle model: thermal noise power (added before detection and
  /// before TVG) is this far below a flat seabed of the default material at maximum range.
  /// Paper model (image domain, after TVG): the mean of the Rayleigh term is this far below the
  /// calibrated mid-range seabed level.
  double snr_at_max_range_db = 20.0;
  bool texture = true;  ///< K-distribution texture from the materials' shape nu
  /// Size of the seabed cells whose speckle is frozen (the same for every ping that sees them),
  /// metres, >= 0; 0 = the sonar's range resolution.
  double freeze_cell_m = 0.0;
};

/// TVG and quantisation into the output sample range.
struct OutputScaling {
  TvgLaw tvg = TvgLaw::spherical;  ///< 30 log R + 2 alpha R (alpha = the simulation's)
  double max_value = 32767.0;      ///< XTF u16 profile
  bool round_to_integer = true;
  /// Gain before quantisation, dB; NaN = automatic: the TVG'd mean of a flat seabed of the
  /// default material at mid range maps to max_value / 16 (computed once per run, global).
  double gain_db = std::numeric_limits<double>::quiet_NaN();
};

struct SimulationConfig {
  SonarConfig sonar;
  PhysicsConfig physics;
  QualityConfig quality;
  NoiseConfig noise;
  OutputScaling output;
  bool truth = true;  ///< per-sample truth in the rendered pings
  /// Also output the noise-free samples of every ping (SideOutput::clean_samples), rendered in
  /// the same call as the noisy ones.
  bool clean_samples = false;
  std::uint64_t seed = 1;  ///< every random draw derives from it
  unsigned threads = 0;    ///< 0 = hardware concurrency; output identical for any value
  void validate() const;
};

/// One side's output, samples ordered NEAR -> FAR.
struct SideOutput {
  std::vector<float> samples;   ///< output units (after TVG and quantisation)
  std::uint32_t saturated = 0;  ///< samples clamped at OutputScaling::max_value
  std::uint32_t invalid = 0;    ///< samples that overflowed to a non-finite value, written as 0
  /// The same samples without noise (same TVG, gain, clamping and rounding), NEAR -> FAR; empty
  /// unless SimulationConfig::clean_samples.
  std::vector<float> clean_samples;
  // Truth (empty unless SimulationConfig::truth).
  std::vector<SampleClass> truth_class;
  std::vector<std::int32_t> truth_label;  ///< object id, 0 seabed, -1 none
  std::vector<float> truth_grazing_rad;   ///< NaN where no seabed contributes
  std::vector<double> truth_ground_x_m;   ///< local frame; NaN where none
  std::vector<double> truth_ground_y_m;
};

struct RenderedPing {
  PingPose pose;  ///< as given, with the noise key the Simulator assigned if it was unset
  SideOutput port;
  SideOutput starboard;
};

/// What a sink is told before the first ping of a run (Simulator::run).
struct RunDescription {
  SimulationConfig config;         ///< the configuration the pings are rendered with
  double gain_db = 0.0;            ///< the quantiser gain actually applied (automatic resolved), dB
  double absorption_db_per_m = 0;  ///< one-way absorption alpha used by physics and TVG, dB/m
  std::uint64_t total_pings = 0;   ///< pings that will be handed to ping()
  std::size_t line_count = 0;      ///< survey lines
};

/// Receives rendered pings in survey order, one at a time (streaming: memory does not grow with
/// survey length). Simulator::run calls, in order: begin() once; per line begin_line(), ping()
/// for each of its pings, end_line(); finish() once after the last line. If anything throws
/// (rendering, a sink, a progress callback) it calls abort() instead of the remaining hooks and
/// rethrows: a sink then discards partial output. Every hook is a no-op by default.
class PingSink {
 public:
  virtual ~PingSink() = default;
  virtual void begin(const RunDescription& /*run*/) {}
  virtual void begin_line(std::size_t /*line*/) {}
  virtual void ping(const RenderedPing& /*ping*/) {}
  virtual void end_line(std::size_t /*line*/) {}
  virtual void finish() {}
  /// The run failed: release resources and leave no partial files. Must not throw.
  virtual void abort() noexcept {}
};

/// Cumulative time split of the renderer, seconds summed over threads.
struct RenderTimings {
  double profile_s = 0.0;
  double render_s = 0.0;  ///< horizon sweep, clipping, integration
  double noise_s = 0.0;   ///< noise, TVG, quantisation
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

  /// Renders every ping of `survey` on `config.threads` threads and hands them to `sink` in
  /// order, with the lifecycle documented on PingSink (begin ... finish, or abort on an
  /// exception, which is then rethrown). `progress(done, total)` is called from the calling
  /// thread after each block.
  RenderTimings run(const Survey& survey, PingSink& sink,
                    const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const;

  double absorption_db_per_m() const { return alpha_db_per_m_; }
  double gain_db() const { return quantizer_.gain_db; }
  double thermal_noise_power() const { return noise_power_; }
  const SimulationConfig& config() const { return config_; }
  const Scene& scene() const { return *scene_; }
  const std::shared_ptr<const Scene>& shared_scene() const { return scene_; }
  const SideParams& side_params() const { return side_; }
  const AlongTrackChoice& along_track() const { return along_track_; }

 private:
  RenderTimings run_pings(const Survey& survey, PingSink& sink,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress) const;
  void render_side_output(const PingPose& pose, std::uint64_t noise_key, bool starboard,
                          Workspace& ws, SideOutput& out, RenderTimings* timings) const;
  /// TVG x gain (unless `scaled`), clamping and rounding of ws.accum into `out`; counts
  /// saturated and non-finite samples.
  void quantise(const Workspace& ws, bool scaled, std::vector<float>& out, std::uint32_t& saturated,
                std::uint32_t& invalid) const;
  /// Sums the planes' noise-free intensities of one side into ws.accum; the echo is left
  /// holding the central plane (rendered last, with truth if `truth`).
  struct SideGeometry {
    Eigen::Vector2d nadir_xy_m, central_dir;
  };
  SideGeometry render_planes(const PingPose& pose, bool starboard, const AlongTrackPlanes& planes,
                             bool truth, Workspace& ws, RenderTimings* timings) const;
  AlongTrackChoice choose_along_track_planes(const std::vector<PingPose>& pilot) const;

  std::shared_ptr<const Scene> scene_;
  /// Automatic noise keys handed out so far (PingPose::ping_index unset).
  mutable std::atomic<std::uint64_t> automatic_keys_{0};
  SimulationConfig config_;
  SideParams side_;
  double alpha_db_per_m_ = 0.0;
  Tvg tvg_;
  Quantizer quantizer_;
  double noise_power_ = 0.0;
  double paper_sigma_out_ = 0.0;  // Rayleigh sigma of the paper noise, output units
  AlongTrackPlanes planes_;
  AlongTrackChoice along_track_;
};

}  // namespace sonarsynth
