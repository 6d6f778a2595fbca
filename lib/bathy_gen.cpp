// SPDX-License-Identifier: MIT
#include "sonarsynth/bathy_gen.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/keyed_random.hpp"
#include "sonarsynth/render_math.hpp"
#include "worker_threads.hpp"

namespace sonarsynth {
namespace {

constexpr int kGradientCount = 64;

struct GradientTable {
  std::array<double, kGradientCount> gx{};
  std::array<double, kGradientCount> gy{};
  GradientTable() {
    for (int i = 0; i < kGradientCount; ++i) {
      const double a = 2.0 * kPi * static_cast<double>(i) / kGradientCount;
      gx[static_cast<std::size_t>(i)] = std::cos(a);
      gy[static_cast<std::size_t>(i)] = std::sin(a);
    }
  }
};

const GradientTable& gradients() {
  static const GradientTable table;
  return table;
}

// Variance of gradient_noise() over the plane with the 64-direction gradient table, measured
// once as the mean of noise^2 over 8 seeds x 10^6 points spread over ~3.3e4 lattice cells
// (0.0465, mean 3e-5). Used to turn Fbm::rms_m into an amplitude.
constexpr double kGradientNoiseVariance = 0.0465;

double fade(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Per-(seed, octave) key, so a lattice corner costs one more mix per coordinate.
std::uint64_t octave_key(std::uint64_t seed, std::uint64_t octave) {
  return splitmix64(seed ^ splitmix64(octave ^ 0x6f63746176650000ULL));
}

// Gradient noise along a row (v fixed): the row's lattice hashes are computed once per row and
// the corners' gradients once per lattice cell entered, not per point (a cell spans
// base_wavelength / cell nodes on the first octave).
class RowNoise {
 public:
  RowNoise(std::uint64_t key, double v) : key_(key) {
    const double fv = std::floor(v);
    tv_ = v - fv;
    const auto iv = static_cast<std::uint64_t>(static_cast<std::int64_t>(fv));
    hv0_ = splitmix64(iv);
    hv1_ = splitmix64(iv + 1);
    sv_ = fade(tv_);
  }
  double operator()(double u) {
    const GradientTable& g = gradients();
    const double fu = render_math::floor_fast(u);
    const double tu = u - fu;
    const auto iu = static_cast<std::uint64_t>(static_cast<std::int64_t>(fu));
    if (!have_ || iu != iu_) {
      if (have_ && iu == iu_ + 1) {  // the next cell: its left corners are the old right ones
        i00_ = i10_;
        i01_ = i11_;
      } else {
        i00_ = index(iu, hv0_);
        i01_ = index(iu, hv1_);
      }
      i10_ = index(iu + 1, hv0_);
      i11_ = index(iu + 1, hv1_);
      iu_ = iu;
      have_ = true;
    }
    const double n00 = g.gx[i00_] * tu + g.gy[i00_] * tv_;
    const double n10 = g.gx[i10_] * (tu - 1.0) + g.gy[i10_] * tv_;
    const double n01 = g.gx[i01_] * tu + g.gy[i01_] * (tv_ - 1.0);
    const double n11 = g.gx[i11_] * (tu - 1.0) + g.gy[i11_] * (tv_ - 1.0);
    const double su = fade(tu);
    const double a = n00 + su * (n10 - n00);
    const double b = n01 + su * (n11 - n01);
    return a + sv_ * (b - a);
  }

 private:
  std::size_t index(std::uint64_t cu, std::uint64_t hv) const {
    return static_cast<std::size_t>(splitmix64(key_ ^ splitmix64(cu ^ hv)) >> 58);
  }
  std::uint64_t key_, hv0_ = 0, hv1_ = 0, iu_ = 0;
  double tv_ = 0.0, sv_ = 0.0;
  std::size_t i00_ = 0, i10_ = 0, i01_ = 0, i11_ = 0;
  bool have_ = false;
};

// Gradient noise at (u, v) for a per-(seed, octave) key: splitmix64 of (key, floor(u),
// floor(v)) picks each lattice corner's gradient. The row evaluator at a single point.
double noise_with_key(double u, double v, std::uint64_t key) {
  return RowNoise(key, v)(u);
}

// The octaves of an fbm component: amplitude, frequency, key and lattice offset of each.
struct FbmOctaves {
  struct Octave {
    double amplitude, freq, ou, ov;
    std::uint64_t key;
  };
  std::vector<Octave> octaves;
  FbmOctaves(const bathy::Fbm& f, std::uint64_t seed) {
    double sum_sq = 0.0;
    double a = 1.0;
    for (int k = 0; k < f.octaves; ++k, a *= f.persistence) sum_sq += a * a;
    const double scale = f.rms_m / std::sqrt(kGradientNoiseVariance * sum_sq);
    const std::uint64_t s = seed + f.seed_offset;
    double amplitude = scale;
    double freq = 1.0 / f.base_wavelength_m;
    for (int k = 0; k < f.octaves; ++k) {
      const std::uint64_t key = octave_key(s, static_cast<std::uint64_t>(k));
      // Per-octave lattice offset so that the octaves' zeros (lattice points) do not coincide.
      const double ou = 256.0 * uniform_from_bits(splitmix64(key ^ 1));
      const double ov = 256.0 * uniform_from_bits(splitmix64(key ^ 2));
      octaves.push_back({amplitude, freq, ou, ov, key});
      amplitude *= f.persistence;
      freq *= 2.0;
    }
  }
};

// The plane waves of a ripple field (bathy::Ripples, bandwidth > 0): wavevectors
// k0 n + q_j with q_j ~ N(0, (bandwidth k0)^2 I), phases psi_j ~ U(0, 2 pi), from splitmix64 of
// (seed + seed_offset) only, so every row and every grid sharing nodes sees the same field.
struct RippleModes {
  std::vector<double> kx, ky, psi;
  double scale = 1.0 / std::sqrt(static_cast<double>(bathy::kRippleModes));
  RippleModes(const bathy::Ripples& r, std::uint64_t seed) {
    const double k0 = 2.0 * kPi / r.wavelength_m;
    const double nx = std::cos(r.crest_azimuth_rad);
    const double ny = -std::sin(r.crest_azimuth_rad);
    const double sigma = r.bandwidth * k0;
    const std::uint64_t key = splitmix64((seed + r.seed_offset) ^ 0x726970706c657300ULL);
    for (int j = 0; j < bathy::kRippleModes; ++j) {
      const auto uj = static_cast<std::uint64_t>(j);
      const NormalPair q = keyed_normal_pair(key, uj, 0);
      kx.push_back(k0 * nx + sigma * q.n1);
      ky.push_back(k0 * ny + sigma * q.n2);
      psi.push_back(2.0 * kPi * uniform_from_bits(keyed_hash(key, uj, 2)));
    }
  }
};

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("bathymetry generator: " + what);
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);  // "0.5", not "0.500000"
  return buf;
}

// Adds one component along a row of nodes (x = x0 + c dx, fixed y) into acc.
struct RowAdder {
  double y;
  double x0;
  double dx;
  std::uint64_t seed;
  std::vector<double>& acc;

  void operator()(const bathy::Plane& p) const {
    const double zy = p.slope_y * (y - p.ref_y_m);
    for (std::size_t c = 0; c < acc.size(); ++c) {
      acc[c] += zy + p.slope_x * (x0 + static_cast<double>(c) * dx - p.ref_x_m);
    }
  }
  void operator()(const bathy::Ripples& r) const {
    if (r.bandwidth > 0.0) {
      add_ripple_field(r);
      return;
    }
    // Across-crest unit vector: the crest direction (sin a, cos a) turned 90 deg clockwise.
    const double nx = std::cos(r.crest_azimuth_rad);
    const double ny = -std::sin(r.crest_azimuth_rad);
    const double k = 2.0 * kPi / r.wavelength_m;
    for (std::size_t c = 0; c < acc.size(); ++c) {
      const double x = x0 + static_cast<double>(c) * dx;
      const double t = k * (nx * (x - r.ref_x_m) + ny * (y - r.ref_y_m));
      acc[c] += r.amplitude_m * std::cos(t + r.asymmetry * std::sin(t));
    }
  }
  // The narrow-band field of bathy::Ripples (bandwidth > 0): the modes' phasors advance along
  // the row by one complex multiplication per node, re-anchored (sin, cos) every kAnchor nodes
  // so that rounding never accumulates over more than kAnchor steps (~1e-14 rad).
  void add_ripple_field(const bathy::Ripples& r) const {
    const RippleModes modes(r, seed);
    constexpr std::size_t kAnchor = 64;
    const std::size_t n = modes.kx.size();
    std::vector<double> re(n), im(n), step_re(n), step_im(n);
    for (std::size_t j = 0; j < n; ++j) {
      step_re[j] = std::cos(modes.kx[j] * dx);
      step_im[j] = std::sin(modes.kx[j] * dx);
    }
    const double norm = 1.0 / std::sqrt(std::tgamma(1.0 + r.amplitude_variation));
    const double v = r.amplitude_variation;
    for (std::size_t c = 0; c < acc.size(); ++c) {
      if (c % kAnchor == 0) {
        const double x = x0 + static_cast<double>(c) * dx;
        for (std::size_t j = 0; j < n; ++j) {
          const double ph =
              modes.kx[j] * (x - r.ref_x_m) + modes.ky[j] * (y - r.ref_y_m) + modes.psi[j];
          re[j] = std::cos(ph);
          im[j] = std::sin(ph);
        }
      }
      double wr = 0.0, wi = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        wr += re[j];
        wi += im[j];
        const double a = re[j] * step_re[j] - im[j] * step_im[j];
        im[j] = re[j] * step_im[j] + im[j] * step_re[j];
        re[j] = a;
      }
      wr *= modes.scale;
      wi *= modes.scale;
      const double m = std::sqrt(wr * wr + wi * wi);
      if (!(m > 0.0)) continue;
      const double envelope = (v == 1.0 ? m : std::pow(m, v)) * norm;
      double shape = wr / m;  // cos t
      if (r.asymmetry > 0.0) {
        const double t = std::atan2(wi, wr);
        shape = std::cos(t + r.asymmetry * std::sin(t));
      }
      acc[c] += r.amplitude_m * envelope * shape;
    }
  }
  void operator()(const bathy::Fbm& f) const {
    const FbmOctaves octaves(f, seed);
    for (const FbmOctaves::Octave& o : octaves.octaves) {
      RowNoise row(o.key, y * o.freq + o.ov);
      for (std::size_t c = 0; c < acc.size(); ++c) {
        const double x = x0 + static_cast<double>(c) * dx;
        acc[c] += o.amplitude * row(x * o.freq + o.ou);
      }
    }
  }
  void operator()(const bathy::Seamount& m) const {
    const double inv = -0.5 / (m.radius_m * m.radius_m);
    const double dy2 = (y - m.centre_y_m) * (y - m.centre_y_m);
    for (std::size_t c = 0; c < acc.size(); ++c) {
      const double ddx = x0 + static_cast<double>(c) * dx - m.centre_x_m;
      acc[c] += m.height_m * std::exp(inv * (ddx * ddx + dy2));
    }
  }
  void operator()(const bathy::Scarp& s) const {
    // Right-hand normal of the strike direction (sin a, cos a): (cos a, -sin a).
    const double nx = std::cos(s.azimuth_rad);
    const double ny = -std::sin(s.azimuth_rad);
    for (std::size_t c = 0; c < acc.size(); ++c) {
      const double x = x0 + static_cast<double>(c) * dx;
      const double d = nx * (x - s.x_m) + ny * (y - s.y_m);
      acc[c] += 0.5 * s.height_m * std::tanh(2.0 * d / s.width_m);
    }
  }
};

// Largest depth or relief a generator accepts, metres: deeper than the deepest ocean (10,935 m)
// and higher than any seamount above its base; beyond it a value is a typo, not a seabed.
constexpr double kMaxReliefM = 11000.0;

struct Validator {
  std::size_t index;
  std::string at() const { return "component " + std::to_string(index) + ": "; }
  void operator()(const bathy::Plane& p) const {
    require(std::isfinite(p.slope_x) && std::isfinite(p.slope_y),
            at() + "plane slope is not finite. Violated constraint: finite slope");
    require(std::isfinite(p.ref_x_m) && std::isfinite(p.ref_y_m),
            at() + "plane reference not finite");
  }
  void operator()(const bathy::Ripples& r) const {
    require(std::isfinite(r.wavelength_m) && r.wavelength_m > 0.0,
            at() + "ripples wavelength_m = " + num(r.wavelength_m) +
                ". Violated constraint: wavelength_m > 0");
    require(std::isfinite(r.amplitude_m) && r.amplitude_m >= 0.0 && r.amplitude_m <= kMaxReliefM,
            at() + "ripples amplitude_m = " + num(r.amplitude_m) +
                ". Violated constraint: 0 <= amplitude_m <= " + num(kMaxReliefM));
    require(r.asymmetry >= 0.0 && r.asymmetry < 1.0,
            at() + "ripples asymmetry = " + num(r.asymmetry) +
                ". Violated constraint: 0 <= asymmetry < 1");
    require(std::isfinite(r.crest_azimuth_rad), at() + "ripples crest azimuth is not finite");
    require(r.bandwidth >= 0.0 && r.bandwidth <= 0.5,
            at() + "ripples bandwidth = " + num(r.bandwidth) +
                ". Violated constraint: 0 <= bandwidth <= 0.5");
    require(r.amplitude_variation >= 0.0 && r.amplitude_variation <= 1.0,
            at() + "ripples amplitude_variation = " + num(r.amplitude_variation) +
                ". Violated constraint: 0 <= amplitude_variation <= 1");
  }
  void operator()(const bathy::Fbm& f) const {
    require(std::isfinite(f.rms_m) && f.rms_m >= 0.0 && f.rms_m <= kMaxReliefM,
            at() + "fbm rms_m = " + num(f.rms_m) +
                ". Violated constraint: 0 <= rms_m <= " + num(kMaxReliefM));
    require(std::isfinite(f.base_wavelength_m) && f.base_wavelength_m > 0.0,
            at() + "fbm base_wavelength_m = " + num(f.base_wavelength_m) +
                ". Violated constraint: base_wavelength_m > 0");
    require(f.octaves >= 1 && f.octaves <= 24, at() + "fbm octaves = " + std::to_string(f.octaves) +
                                                   ". Violated constraint: 1 <= octaves <= 24");
    require(f.persistence > 0.0 && f.persistence <= 1.0,
            at() + "fbm persistence = " + num(f.persistence) +
                ". Violated constraint: 0 < persistence <= 1");
  }
  void operator()(const bathy::Seamount& m) const {
    require(
        std::isfinite(m.radius_m) && m.radius_m > 0.0,
        at() + "seamount radius_m = " + num(m.radius_m) + ". Violated constraint: radius_m > 0");
    require(std::isfinite(m.height_m) && std::isfinite(m.centre_x_m) && std::isfinite(m.centre_y_m),
            at() + "seamount height or centre is not finite");
    require(std::abs(m.height_m) <= kMaxReliefM,
            at() + "seamount height_m = " + num(m.height_m) +
                ". Violated constraint: |height_m| <= " + num(kMaxReliefM));
  }
  void operator()(const bathy::Scarp& s) const {
    require(std::isfinite(s.width_m) && s.width_m > 0.0,
            at() + "scarp width_m = " + num(s.width_m) + ". Violated constraint: width_m > 0");
    require(std::isfinite(s.height_m) && std::isfinite(s.x_m) && std::isfinite(s.y_m) &&
                std::isfinite(s.azimuth_rad),
            at() + "scarp height, position or azimuth is not finite");
    require(std::abs(s.height_m) <= kMaxReliefM,
            at() + "scarp height_m = " + num(s.height_m) +
                ". Violated constraint: |height_m| <= " + num(kMaxReliefM));
  }
};

}  // namespace

bathy::Plane bathy::Plane::from_dip(double slope_rad, double downslope_azimuth_rad, double ref_x,
                                    double ref_y) {
  require(slope_rad >= 0.0 && slope_rad < kPi / 2.0,
          "plane slope = " + num(deg_from_rad(slope_rad)) +
              " deg. Violated constraint: 0 <= slope < 90 deg");
  const double t = std::tan(slope_rad);
  // Heights decrease along (sin az, cos az).
  return {-t * std::sin(downslope_azimuth_rad), -t * std::cos(downslope_azimuth_rad), ref_x, ref_y};
}

double bathy::Fbm::height_m(double x_m, double y_m, std::uint64_t seed) const {
  double z = 0.0;
  for (const FbmOctaves::Octave& o : FbmOctaves(*this, seed).octaves) {
    z += o.amplitude * noise_with_key(x_m * o.freq + o.ou, y_m * o.freq + o.ov, o.key);
  }
  return z;
}

double gradient_noise(double u, double v, std::uint64_t seed, std::uint64_t octave) {
  return noise_with_key(u, v, octave_key(seed, octave));
}

void BathyGenSpec::validate() const {
  require(std::isfinite(depth_m) && depth_m > 0.0 && depth_m <= kMaxReliefM,
          "depth_m = " + num(depth_m) +
              ". Violated constraint: 0 < depth_m <= " + num(kMaxReliefM) + " (the deepest ocean)");
  validate_components();
}

void BathyGenSpec::validate_components() const {
  geometry.validate("bathymetry generator");
  for (std::size_t i = 0; i < components.size(); ++i) std::visit(Validator{i}, components[i]);
  // Features finer than the grid alias into noise: a ripple needs two cells per wavelength.
  const double cell_m = std::max(std::abs(geometry.dx_m), std::abs(geometry.dy_m));
  for (std::size_t i = 0; i < components.size(); ++i) {
    if (const auto* r = std::get_if<bathy::Ripples>(&components[i])) {
      require(r->wavelength_m >= 2.0 * cell_m,
              "component " + std::to_string(i) + ": ripples wavelength_m = " +
                  num(r->wavelength_m) + ". Violated constraint: wavelength_m >= 2 cells (" +
                  num(2.0 * cell_m) + " m), or the grid cannot represent the ripples");
    }
  }
}

GridGeometry BathyGenSpec::centred_geometry(double centre_x_m, double centre_y_m, double width_m,
                                            double height_m, double cell_m) {
  require(std::isfinite(cell_m) && cell_m > 0.0,
          "cell_m = " + num(cell_m) + ". Violated constraint: cell_m > 0");
  require(std::isfinite(width_m) && width_m > 0.0,
          "width_m = " + num(width_m) + ". Violated constraint: width_m > 0");
  require(std::isfinite(height_m) && height_m > 0.0,
          "height_m = " + num(height_m) + ". Violated constraint: height_m > 0");
  const double cols = std::round(width_m / cell_m);
  const double rows = std::round(height_m / cell_m);
  require(cols >= 2.0 && rows >= 2.0 && cols <= 1e6 && rows <= 1e6,
          "grid of " + num(cols) + " x " + num(rows) +
              " cells. Violated constraint: 2 <= width_m / cell_m, height_m / cell_m <= 1e6");
  const auto g10 = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return std::string(buf);
  };
  require(cols * rows <= kMaxCells,
          "grid of " + g10(width_m) + " m x " + g10(height_m) + " m at cell_m = " + g10(cell_m) +
              " has " + g10(cols) + " x " + g10(rows) + " = " + g10(cols * rows) + " cells (" +
              g10(std::ceil(cols * rows * 4.0 / 1048576.0)) +
              " MiB of heights). Violated constraint: cells <= " + g10(kMaxCells) + " (1 GiB)");
  GridGeometry g;
  g.cols = static_cast<std::size_t>(cols);
  g.rows = static_cast<std::size_t>(rows);
  g.dx_m = cell_m;
  g.dy_m = -cell_m;
  g.x0_m = centre_x_m - 0.5 * (cols - 1.0) * cell_m;
  g.y0_m = centre_y_m + 0.5 * (rows - 1.0) * cell_m;
  return g;
}

namespace {

// Every node of spec.geometry: out = float(-depth + components), or with `add`,
// out = out + float(components) (float32 addition; the depth is left out).
void fill_bathymetry(const BathyGenSpec& spec, bool add, std::vector<float>& heights) {
  const GridGeometry& g = spec.geometry;
  const double start = add ? 0.0 : -spec.depth_m;
  unsigned threads = detail::worker_thread_count(spec.num_threads);
  threads = std::max(
      1u, std::min<unsigned>(threads, static_cast<unsigned>(std::min<std::size_t>(g.rows, 256))));

  // Rows are dealt out in interleaved blocks; every node's value depends on its position only.
  auto work = [&](unsigned t) {
    std::vector<double> acc(g.cols);
    constexpr std::size_t kBlock = 16;
    for (std::size_t r0 = t * kBlock; r0 < g.rows; r0 += threads * kBlock) {
      for (std::size_t r = r0; r < std::min(g.rows, r0 + kBlock); ++r) {
        std::fill(acc.begin(), acc.end(), start);
        const RowAdder adder{g.y_of_row(static_cast<double>(r)), g.x0_m, g.dx_m, spec.seed, acc};
        for (const bathy::Component& c : spec.components) std::visit(adder, c);
        float* out = heights.data() + r * g.cols;
        if (add) {
          for (std::size_t c = 0; c < g.cols; ++c) out[c] += static_cast<float>(acc[c]);
        } else {
          for (std::size_t c = 0; c < g.cols; ++c) out[c] = static_cast<float>(acc[c]);
        }
      }
    }
  };
  // Thread t computes its own interleaved rows; a thread the system refuses to start (pids
  // limit) has its share computed here instead, so the result never depends on the count.
  std::vector<std::exception_ptr> errors(threads);
  auto guarded = [&](unsigned t) {
    try {
      work(t);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  std::vector<unsigned> here = {0};
  {
    std::vector<std::jthread> pool;
    for (unsigned t = 1; t < threads; ++t) {
      std::jthread th = detail::try_start_thread([&guarded, t] { guarded(t); });
      if (th.joinable()) {
        pool.push_back(std::move(th));
      } else {
        here.push_back(t);
      }
    }
    for (const unsigned t : here) guarded(t);
  }  // joins the pool
  for (auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace

HeightGrid generate_bathymetry(const BathyGenSpec& spec) {
  spec.validate();
  std::vector<float> heights(spec.geometry.size());
  fill_bathymetry(spec, false, heights);
  return HeightGrid(spec.geometry, std::move(heights));
}

void add_bathymetry_components(const BathyGenSpec& spec, HeightGrid& grid) {
  spec.validate_components();
  const GridGeometry& a = spec.geometry;
  const GridGeometry& b = grid.geometry();
  require(a.x0_m == b.x0_m && a.y0_m == b.y0_m && a.dx_m == b.dx_m && a.dy_m == b.dy_m &&
              a.cols == b.cols && a.rows == b.rows,
          "add_bathymetry_components: the spec's geometry is not the grid's");
  fill_bathymetry(spec, true, grid.mutable_heights());
}

}  // namespace sonarsynth
