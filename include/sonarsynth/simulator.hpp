// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
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
  ProfileOptions profile;
  int gauss_points = 2;        ///< [1, 5]
  int along_track_planes = 1;  ///< K planes across the horizontal beam, [1, 64]
  void validate() const;
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
  bool truth = true;       ///< per-sample truth in the rendered pings
  std::uint64_t seed = 1;  ///< every random draw derives from it
  unsigned threads = 0;    ///< 0 = hardware concurrency; output identical for any value
  void validate() const;
};

/// One side's output, samples ordered NEAR -> FAR.
struct SideOutput {
  std::vector<float> samples;  ///< output units (after TVG and quantisation)
  // Truth (empty unless SimulationConfig::truth).
  std::vector<SampleClass> truth_class;
  std::vector<std::int32_t> truth_label;  ///< object id, 0 seabed, -1 none
  std::vector<float> truth_grazing_rad;   ///< NaN where no seabed contributes
  std::vector<double> truth_ground_x_m;   ///< local frame; NaN where none
  std::vector<double> truth_ground_y_m;
};

struct RenderedPing {
  PingPose pose;
  SideOutput port;
  SideOutput starboard;
};

/// Receives rendered pings in survey order, one at a time (streaming: memory does not grow with
/// survey length).
class PingSink {
 public:
  virtual ~PingSink() = default;
  virtual void begin_line(std::size_t /*line*/) {}
  virtual void ping(const RenderedPing& ping) = 0;
  virtual void end_line(std::size_t /*line*/) {}
};

/// Cumulative time split of the renderer, seconds summed over threads.
struct RenderTimings {
  double profile_s = 0.0;
  double render_s = 0.0;  ///< horizon sweep, clipping, integration
  double noise_s = 0.0;   ///< noise, TVG, quantisation
};

/// Renders pings of a survey over a scene. Construction derives the global calibration
/// (absorption, gain, noise level) once; render_ping() is then a pure function of the pose.
class Simulator {
 public:
  Simulator(const Scene& scene, const SimulationConfig& config, double reference_altitude_m);
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
  void render_ping(const PingPose& pose, Workspace& ws, RenderedPing& out,
                   RenderTimings* timings = nullptr) const;

  /// Renders every ping of `survey` on `config.threads` threads and hands them to `sink` in
  /// order. `progress(done, total)` is called from the calling thread after each block.
  RenderTimings run(const Survey& survey, PingSink& sink,
                    const std::function<void(std::uint64_t, std::uint64_t)>& progress = {}) const;

  double absorption_db_per_m() const { return alpha_db_per_m_; }
  double gain_db() const { return quantizer_.gain_db; }
  double thermal_noise_power() const { return noise_power_; }
  const SimulationConfig& config() const { return config_; }
  const SideParams& side_params() const { return side_; }

 private:
  void render_side_output(const PingPose& pose, bool starboard, Workspace& ws, SideOutput& out,
                          RenderTimings* timings) const;

  const Scene& scene_;
  SimulationConfig config_;
  SideParams side_;
  double alpha_db_per_m_ = 0.0;
  Tvg tvg_;
  Quantizer quantizer_;
  double noise_power_ = 0.0;
  double paper_sigma_out_ = 0.0;        // Rayleigh sigma of the paper noise, output units
  std::vector<double> plane_psi_rad_;   // along-track planes: azimuth offsets
  std::vector<double> plane_beta_rad_;  // and their share of beta_eff
};

}  // namespace sonarsynth
