// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth {

/// Uniform-angle ray casting over a beam-plane profile: the method most side-scan simulators use
/// (docs/physics.md §2.3), kept as a COMPARISON method for the benchmarks, not a
/// product path.
///
/// `rays` rays are spread uniformly in depression angle over the angular extent of the profile
/// as seen from the sensor (the smallest to the largest node depression), ray k at the centre of
/// its interval of width dtheta. Each ray's first hit is exact: the horizon (running minimum of
/// tan(depression) over the nodes) is non-increasing, so the first node at or above the ray is
/// found by binary search and the hit is the intersection with the facet ending there. A hit at
/// slant range r on a facet with incidence cosine cos(phi) returns (Gwon's per-ray law, §1.5)
///   K sigma_b(phi) / cos(phi) b^2(theta - theta_axis) beta_eff dtheta r^2 g(r) 10^(-2 alpha r/10)
/// with g = r^-4 (spreading on) or 1, which is K mu cos(phi) b^2 beta dtheta / r^2 for Lambert:
/// the per-ray power is SUMMED into the sample(s) whose window holds r (a rectangular pulse
/// window as in render_side). Rays through a hole (a facet touching a NaN node) or past the
/// profile end are lost. Truth arrays are not filled; SideParams::shadows and gauss_points are
/// ignored (a ray always stops at its first hit). The profile's closed sections (objects off the
/// seabed) are ignored too: the comparison is on heightfields.
///
/// Cost O(nodes + rays log nodes). Throws InputError if params or the profile are invalid or
/// rays == 0.
void render_side_rays(const BeamProfile& profile, const SideParams& params, std::size_t rays,
                      SideEcho& out);

}  // namespace sonarsynth
