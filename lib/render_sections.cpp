// SPDX-License-Identifier: MIT
#include "sonarsynth/render_sections.hpp"

#include <cstdint>

namespace sonarsynth::sections {

bool hidden_by(const Segment& o, double ay, double az, double uy, double uz, double& h0,
               double& h1) {
  double lo = 0.0, hi = 1.0;
  const auto keep = [&](double g0, double g1) {  // keep g0 + t g1 >= 0
    if (g1 == 0.0) return g0 >= 0.0;
    const double t = -g0 / g1;
    if (g1 > 0.0) {
      lo = std::max(lo, t);
    } else {
      hi = std::min(hi, t);
    }
    return lo < hi;
  };
  const double ey = o.y1 - o.y0, ez = o.z1 - o.z0;
  if (!keep(o.y0 * az - o.z0 * ay, o.y0 * uz - o.z0 * uy)) return false;
  if (!keep(ay * o.z1 - az * o.y1, uy * o.z1 - uz * o.y1)) return false;
  if (!keep(-(ey * (az - o.z0) - ez * (ay - o.y0)), -(ey * uz - ez * uy))) return false;
  h0 = lo;
  h1 = hi;
  return true;
}

void subtract_interval(std::vector<double>& v, std::vector<double>& tmp, double h0, double h1) {
  tmp.clear();
  for (std::size_t i = 0; i + 1 < v.size(); i += 2) {
    const double a = v[i], b = v[i + 1];
    if (h1 <= a || h0 >= b) {
      tmp.push_back(a);
      tmp.push_back(b);
      continue;
    }
    if (h0 > a) {
      tmp.push_back(a);
      tmp.push_back(h0);
    }
    if (h1 < b) {
      tmp.push_back(h1);
      tmp.push_back(b);
    }
  }
  v.swap(tmp);
}

void section_occluders(const BeamProfile& prof, double min_y, std::vector<Segment>& out) {
  out.clear();
  const double hs = prof.sensor_z_m;
  const auto base = static_cast<std::int32_t>(prof.seabed_facets());
  for (std::size_t s = 0; s < prof.sections(); ++s) {
    const std::uint32_t first = prof.section_start[s], end = prof.section_start[s + 1];
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t next = k + 1 < end ? k + 1 : first;
      const double y0 = prof.section_y_m[k], z0 = prof.section_z_m[k] - hs;
      const double y1 = prof.section_y_m[next], z1 = prof.section_z_m[next] - hs;
      if (!(y0 * z1 - z0 * y1 > 0.0)) continue;  // seen from behind or edge-on
      const double ta = tan_depression(y0, z0, min_y), tb = tan_depression(y1, z1, min_y);
      out.push_back({y0, z0, y1, z1, std::min(ta, tb), std::max(ta, tb),
                     static_cast<std::uint32_t>(s), base + static_cast<std::int32_t>(k)});
    }
  }
}

}  // namespace sonarsynth::sections
