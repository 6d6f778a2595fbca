// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/render_side.hpp"

// Exact occlusion between the seabed and the closed sections of a beam-plane profile (objects as
// solids, docs/physics.md §2.1 step 3): the geometry render_side uses for them.
namespace sonarsynth::sections {

using Segment = SideEcho::Workspace::Segment;

/// Hidden parts shorter than this (in facet parameter) are round-off at shared or touching
/// points, not occlusion.
constexpr double kMinHidden = 1e-12;

/// tan(depression) of a point relative to the sensor (docs/physics.md §1.1), y guarded at nadir.
inline double tan_depression(double y_rel, double z_rel, double min_y) {
  return -z_rel / std::max(y_rel, min_y);
}

/// The part [h0, h1] of the segment P(t) = a + t u, t in [0, 1] (relative to the sensor), that
/// segment o hides: the points whose ray from the sensor crosses o before reaching them. That
/// set is convex (the wedge of o seen from the sensor, cross(o0, P) >= 0 and cross(P, o1) >= 0,
/// intersected with the far side of o's line), so a straight segment meets it in one interval
/// (Cyrus–Beck clipping). False if it hides nothing. Requires cross(o0, o1) > 0.
bool hidden_by(const Segment& o, double ay, double az, double uy, double uz, double& h0,
               double& h1);

/// Removes [h0, h1] from the sorted disjoint intervals `v` (flattened pairs); `tmp` is scratch.
void subtract_interval(std::vector<double>& v, std::vector<double>& tmp, double h0, double h1);

/// The facets of the profile's closed sections that face the sensor, relative to it, with their
/// tan(depression) range (y guarded at min_y), section and facet index (`out` is cleared first).
void section_occluders(const BeamProfile& prof, double min_y, std::vector<Segment>& out);

}  // namespace sonarsynth::sections
