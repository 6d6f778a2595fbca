// SPDX-License-Identifier: MIT
// One rendering method with its quality knobs, and a ping renderer that runs it on a Scene the
// way Simulator::render_ping does (both sides, K along-track planes weighted by the two-way
// horizontal pattern), returning linear energies per bin (noise off, TVG none).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/ray_renderer.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/scene_profile.hpp"
#include "sonarsynth/simulator.hpp"

namespace bench {

struct Method {
  std::string family;  ///< exact, rays, decimate (chart legend)
  std::string label;   ///< the knob setting, e.g. "gauss=3"
  sonarsynth::ProfileOptions profile;
  int gauss_points = 2;
  int along_track_planes = 1;
  int decimate = 1;      ///< keep every n-th seabed node of the profile (sub-sampled profile)
  std::size_t rays = 0;  ///< > 0: uniform-angle ray casting with this many rays per side
  double cell_m = 0.25;  ///< DEM cell the scene is generated at
  bool is_default = false;
};

/// The library's default quality (QualityConfig{}) at the paper's 0.25 m DEM, with the
/// along-track plane count the Simulator chose for the scene (QualityConfig's default is
/// automatic; benches rendering a single beam plane pass 1).
Method default_method(int along_track_planes = 1);

/// Reusable buffers of render_ping_energy().
struct PingWorkspace {
  sonarsynth::BeamProfile profile, decimated;
  sonarsynth::ProfileScratch scratch;
  sonarsynth::SideEcho echo;
  sonarsynth::SideParams params;
};

/// Linear bin energies of both sides of one ping: out[0..n) port, out[n..2n) starboard.
/// `side` is the Simulator's SideParams (sonar equation), `sonar` gives the along-track planes.
void render_ping_energy(const sonarsynth::Scene& scene, const sonarsynth::SideParams& side,
                        const sonarsynth::SonarConfig& sonar, const sonarsynth::PingPose& pose,
                        const Method& m, PingWorkspace& ws, std::vector<double>& out);

/// Renders one side of a profile with the method's renderer (render_side or ray casting), after
/// the method's decimation.
void render_profile(const sonarsynth::BeamProfile& profile, const sonarsynth::SideParams& params,
                    const Method& m, PingWorkspace& ws, sonarsynth::SideEcho& out);

}  // namespace bench
