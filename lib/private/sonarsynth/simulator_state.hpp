// SPDX-License-Identifier: MIT
// The per-thread workspace and the run-wide calibration of a Simulator (lib/simulator.cpp,
// lib/simulator_planes.cpp, lib/simulator_run.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/noise.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/scene_profile.hpp"
#include "sonarsynth/sensor_effects.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/tvg.hpp"

namespace sonarsynth {

struct Simulator::Workspace {
  SideParams params;
  BeamProfile profile;
  ProfileScratch scratch;
  SideEcho echo;
  std::vector<double> accum;
  std::vector<std::uint64_t> keys;
  std::vector<std::uint64_t> noise_keys;
  std::vector<double> nu;
  std::vector<double> tvg_gain;  // linear TVG x quantiser gain per sample (precomputed)
  SensorMeanTables sensor_mean;  // volume / fill per sample over tvg_gain (precomputed)
  // splitmix64(i) per sample index (precomputed): the per-ping part of the (ping, side, sample)
  // key then costs one splitmix64 per sample (see ping_sample_keys).
  std::vector<std::uint64_t> sample_hash;
  DetectorScratch detector;
  AlongTrackPlanes refined;  // the planes of a ping side that sees a small object
  std::vector<double> refine_scratch;
  // Refined sides: per sample, the energy of the planes whose contributor is an object, and the
  // truth of the brightest of them (see render_planes).
  std::vector<double> object_energy, best_object_energy;
  SideEcho best_object;
  // Object window (Calibration::object_planes): the object planes' profiles, built before the
  // run planes are rendered and rendered after them over the window, their echo and sum.
  std::vector<BeamProfile> object_profiles;
  SideEcho window_echo;
  std::vector<double> window_accum;
  /// Pilot pings of the seabed plane count: every profile without its closed sections.
  bool seabed_only = false;
};

struct Simulator::Calibration {
  SideParams side;
  Tvg tvg;
  Quantizer quantizer;
  AlongTrackPlanes planes;
  /// Set when render.quality.small_object_planes is on and the scene has objects.
  std::unique_ptr<ObjectPlaneRefiner> refiner;
  /// Automatic plane count with more planes for objects than for the seabed
  /// (AlongTrackChoice::object_planes > planes): the planes of the object window, and the
  /// footprints that tell which ping sides may see an object (ObjectPlaneRefiner::sees_object).
  AlongTrackPlanes object_planes;
  std::unique_ptr<ObjectPlaneRefiner> object_finder;
  SensorModel sensor;
};

}  // namespace sonarsynth
