// SPDX-License-Identifier: MIT
#include "sonarsynth/object_roughness.hpp"

#include <algorithm>
#include <cmath>

#include "sonarsynth/keyed_random.hpp"

namespace sonarsynth {
namespace {
constexpr std::uint64_t kRoughnessSeed = 0x726f756768ULL;  // "rough"
// At most this many nodes per subdivided facet (a long facet with a tiny length is capped).
constexpr double kMaxPiecesPerFacet = 4096.0;
}  // namespace

RoughnessWaves::RoughnessWaves(std::int32_t object_id) {
  const auto key = static_cast<std::uint64_t>(static_cast<std::uint32_t>(object_id));
  for (int m = 0; m < kWaves; ++m) {
    const auto st = static_cast<std::uint64_t>(8 * m);
    const auto i = static_cast<std::size_t>(m);
    const NormalPair a = keyed_normal_pair(kRoughnessSeed, key, st);
    const NormalPair b = keyed_normal_pair(kRoughnessSeed, key, st + 2);
    nx_[i] = a.n1;
    ny_[i] = a.n2;
    nz_[i] = b.n1;
    phase_[i] =
        6.283185307179586476925 * uniform_from_bits(keyed_hash(kRoughnessSeed, key, st + 4));
  }
}

double RoughnessWaves::unit_height(double x_m, double y_m, double z_m, double length_m) const {
  const double inv = 1.0 / length_m;
  const double x = x_m * inv, y = y_m * inv, z = z_m * inv;
  double sum = 0.0;
  for (std::size_t m = 0; m < static_cast<std::size_t>(kWaves); ++m) {
    sum += std::cos(nx_[m] * x + ny_[m] * y + nz_[m] * z + phase_[m]);
  }
  return sum * std::sqrt(2.0 / kWaves);
}

bool any_rough_material(const MaterialTable& materials) {
  return std::any_of(materials.all().begin(), materials.all().end(),
                     [](const Material& m) { return m.roughness_rms_m > 0.0; });
}

void roughen_sections(BeamProfile& out, std::size_t first_section, std::int32_t object_id,
                      const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across_dir,
                      const MaterialTable& materials, RoughnessScratch& s) {
  const std::size_t ns = out.sections();
  if (first_section >= ns) return;
  const std::size_t node0 = out.section_start[first_section];
  const std::size_t node_end = out.section_start[ns];
  bool rough = false;
  for (std::size_t sec = first_section; sec < ns && !rough; ++sec) {
    for (std::size_t k = out.section_start[sec]; k < out.section_start[sec + 1] && !rough; ++k) {
      rough = materials[out.section_facet_mat(sec, k)].roughness_rms_m > 0.0;
    }
  }
  if (!rough) return;

  // Take the sections off the profile.
  const auto off = static_cast<std::ptrdiff_t>(node0);
  s.y.assign(out.section_y_m.begin() + off, out.section_y_m.end());
  s.z.assign(out.section_z_m.begin() + off, out.section_z_m.end());
  s.mat.clear();
  s.start.clear();
  s.label.clear();
  s.section_mat.clear();
  for (std::size_t sec = first_section; sec < ns; ++sec) {
    s.start.push_back(static_cast<std::uint32_t>(out.section_start[sec] - node0));
    s.label.push_back(out.section_label[sec]);
    s.section_mat.push_back(out.section_material[sec]);
    for (std::size_t k = out.section_start[sec]; k < out.section_start[sec + 1]; ++k) {
      s.mat.push_back(out.section_facet_mat(sec, k));
    }
  }
  s.start.push_back(static_cast<std::uint32_t>(node_end - node0));
  out.section_y_m.resize(node0);
  out.section_z_m.resize(node0);
  out.section_start.resize(first_section + 1);
  out.section_label.resize(first_section);
  out.section_material.resize(first_section);
  if (!out.section_facet_material.empty()) out.section_facet_material.resize(node0);

  const RoughnessWaves waves(object_id);
  const auto height = [&](std::uint16_t mat, double y, double z) {
    const Material& m = materials[mat];
    if (!(m.roughness_rms_m > 0.0)) return 0.0;
    const Eigen::Vector2d p = nadir_xy_m + y * across_dir;
    return m.roughness_rms_m * waves.unit_height(p.x(), p.y(), z, m.roughness_length_m);
  };
  for (std::size_t sec = 0; sec + 1 < s.start.size(); ++sec) {
    const std::size_t b = s.start[sec], e = s.start[sec + 1];
    // Subdivide the rough facets.
    s.ry.clear();
    s.rz.clear();
    s.rmat.clear();
    for (std::size_t k = b; k < e; ++k) {
      const std::size_t next = k + 1 < e ? k + 1 : b;
      const std::uint16_t mat = s.mat[k];
      const Material& m = materials[mat];
      const double dy = s.y[next] - s.y[k], dz = s.z[next] - s.z[k];
      double pieces = 1.0;
      if (m.roughness_rms_m > 0.0) {
        pieces = std::ceil(std::hypot(dy, dz) * 3.0 / m.roughness_length_m);
        pieces = std::clamp(pieces, 1.0, kMaxPiecesPerFacet);
      }
      const auto np = static_cast<int>(pieces);
      for (int j = 0; j < np; ++j) {
        const double t = j / pieces;
        s.ry.push_back(s.y[k] + t * dy);
        s.rz.push_back(s.z[k] + t * dz);
        s.rmat.push_back(mat);
      }
    }
    // Displace every node along its normal by the mean height of its two facets.
    const std::size_t rn = s.ry.size();
    s.h.resize(2 * rn);  // normal y, normal z per node, then overwritten in place
    for (std::size_t k = 0; k < rn; ++k) {
      const std::size_t prev = k == 0 ? rn - 1 : k - 1, next = k + 1 < rn ? k + 1 : 0;
      double ny = 0.0, nz = 0.0;
      for (const auto& [a, c] : {std::pair{prev, k}, std::pair{k, next}}) {
        const double dy = s.ry[c] - s.ry[a], dz = s.rz[c] - s.rz[a];
        const double len = std::hypot(dy, dz);
        if (len > 0.0) {  // outward normal of the clockwise facet a -> c (beam_profile.hpp)
          ny += -dz / len;
          nz += dy / len;
        }
      }
      const double nl = std::hypot(ny, nz);
      const double dh =
          0.5 * (height(s.rmat[prev], s.ry[k], s.rz[k]) + height(s.rmat[k], s.ry[k], s.rz[k]));
      s.h[2 * k] = nl > 0.0 ? dh * ny / nl : 0.0;
      s.h[2 * k + 1] = nl > 0.0 ? dh * nz / nl : 0.0;
    }
    for (std::size_t k = 0; k < rn; ++k) {
      s.ry[k] = std::max(0.0, s.ry[k] + s.h[2 * k]);
      s.rz[k] += s.h[2 * k + 1];
    }
    const bool one_material =
        std::all_of(s.rmat.begin(), s.rmat.end(), [&](std::uint16_t m) { return m == s.rmat[0]; });
    if (one_material && out.section_facet_material.empty()) {
      out.add_section(s.ry.data(), s.rz.data(), rn, s.label[sec], s.section_mat[sec]);
    } else {
      out.add_section(s.ry.data(), s.rz.data(), s.rmat.data(), rn, s.label[sec],
                      s.section_mat[sec]);
    }
  }
}

}  // namespace sonarsynth
