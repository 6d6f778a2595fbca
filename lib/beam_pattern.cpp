// SPDX-License-Identifier: MIT
#include "sonarsynth/beam_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/render_math.hpp"

namespace sonarsynth {
namespace {
constexpr double kPiD = 3.14159265358979323846;
constexpr double kFourLn2 = 2.772588722239781238;  // 4 ln 2

void bad(const std::string& what) {
  throw InputError("vertical beam: " + what);
}

void check_width(const char* name, double v) {
  if (!(std::isfinite(v) && v > 0.0 && v <= kPiD)) {
    bad(std::string(name) + " = " + std::to_string(v) + ". Violated constraint: 0 < " + name +
        " <= pi");
  }
}

double sinc(double x) {
  return std::abs(x) < 1e-8 ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}
}  // namespace

void VerticalBeamPattern::validate() const {
  switch (shape) {
    case VerticalBeamShape::uniform:
      return;
    case VerticalBeamShape::paper_sine_pair:
      check_width("upper_half_width_rad", upper_half_width_rad);
      check_width("lower_half_width_rad", lower_half_width_rad);
      return;
    case VerticalBeamShape::gaussian:
      check_width("width_3db_rad", width_3db_rad);
      return;
    case VerticalBeamShape::sinc:
      if (!(std::isfinite(height_over_wavelength) && height_over_wavelength > 0.0)) {
        bad("height_over_wavelength = " + std::to_string(height_over_wavelength) +
            ". Violated constraint: height_over_wavelength > 0");
      }
      return;
    case VerticalBeamShape::table: {
      const std::size_t n = table_off_axis_rad.size();
      if (n < 2 || table_gain_db.size() != n) {
        bad("table sizes " + std::to_string(n) + " angles, " +
            std::to_string(table_gain_db.size()) +
            " gains. Violated constraint: angles.size() == gains.size() >= 2");
      }
      for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(table_off_axis_rad[i]) || !std::isfinite(table_gain_db[i]) ||
            (i > 0 && !(table_off_axis_rad[i] > table_off_axis_rad[i - 1]))) {
          bad("table entry " + std::to_string(i) + " (angle " +
              std::to_string(table_off_axis_rad[i]) + " rad, gain " +
              std::to_string(table_gain_db[i]) +
              " dB). Violated constraint: finite, angles strictly increasing");
        }
      }
      return;
    }
  }
  bad("unknown shape. Violated constraint: shape is one of the VerticalBeamShape values");
}

double VerticalBeamPattern::one_way(double off) const {
  switch (shape) {
    case VerticalBeamShape::uniform:
      return 1.0;
    case VerticalBeamShape::paper_sine_pair:
      return render_math::paper_sine_pair(off, upper_half_width_rad, lower_half_width_rad);
    case VerticalBeamShape::gaussian: {
      const double x = off / width_3db_rad;
      return std::exp(-kFourLn2 * x * x);
    }
    case VerticalBeamShape::sinc: {
      const double d = sinc(kPiD * height_over_wavelength * std::sin(off));
      return d * d;
    }
    case VerticalBeamShape::table: {
      const auto& a = table_off_axis_rad;
      const auto& g = table_gain_db;
      double db;
      if (off <= a.front()) {
        db = g.front();
      } else if (off >= a.back()) {
        db = g.back();
      } else {
        const auto it = std::upper_bound(a.begin(), a.end(), off);
        const auto k = static_cast<std::size_t>(it - a.begin());
        const double s = (off - a[k - 1]) / (a[k] - a[k - 1]);
        db = g[k - 1] + s * (g[k] - g[k - 1]);
      }
      return std::pow(10.0, db / 10.0);
    }
  }
  return 0.0;
}

double beta_eff_uniform_line_array_rad(double array_length_m, double wavelength_m) {
  if (!(std::isfinite(array_length_m) && array_length_m > 0.0)) {
    throw InputError("beta_eff: array_length_m = " + std::to_string(array_length_m) +
                     ". Violated constraint: array_length_m > 0");
  }
  if (!(std::isfinite(wavelength_m) && wavelength_m > 0.0)) {
    throw InputError("beta_eff: wavelength_m = " + std::to_string(wavelength_m) +
                     ". Violated constraint: wavelength_m > 0");
  }
  // 5-point Gauss–Legendre on [-1, 1] (Abramowitz & Stegun 25.4).
  static constexpr double x5[5] = {-0.90617984593866399280, -0.53846931010568309104, 0.0,
                                   0.53846931010568309104, 0.90617984593866399280};
  static constexpr double w5[5] = {0.23692688505618908751, 0.47862867049936646804,
                                   0.56888888888888888889, 0.47862867049936646804,
                                   0.23692688505618908751};
  const double k = kPiD * array_length_m / wavelength_m;
  // Zeros of D in sin(psi) every lambda / L: 16 panels per lobe over psi in [0, pi/2].
  const double lobes = std::max(1.0, array_length_m / wavelength_m);
  const auto panels = static_cast<long>(std::ceil(16.0 * lobes)) + 16;
  const double h = 0.5 * kPiD / static_cast<double>(panels);
  double sum = 0.0;
  for (long p = 0; p < panels; ++p) {
    const double mid = (static_cast<double>(p) + 0.5) * h;
    for (int g = 0; g < 5; ++g) {
      const double d = sinc(k * std::sin(mid + 0.5 * h * x5[g]));
      sum += w5[g] * d * d * d * d;
    }
  }
  return 2.0 * 0.5 * h * sum;  // symmetric: twice the half-range integral
}

double VerticalBeamPattern::width_3db_full_rad() const {
  switch (shape) {
    case VerticalBeamShape::uniform:
      return 0.0;
    case VerticalBeamShape::gaussian:
      return width_3db_rad;
    case VerticalBeamShape::paper_sine_pair:
    case VerticalBeamShape::sinc:
    case VerticalBeamShape::table:
      break;
  }
  // First crossing of b = 1/2 on each side: a scan in 0.001 rad steps, then bisection.
  const auto half_width = [this](double side) {
    constexpr double kStep = 1e-3;
    constexpr double kLimit = 0.5 * kPiD;
    double lo = 0.0;
    for (double hi = kStep; lo < kLimit; lo = hi, hi = std::min(hi + kStep, kLimit)) {
      if (one_way(side * hi) <= 0.5) {
        while (hi - lo > 1e-12) {
          const double mid = 0.5 * (lo + hi);
          (one_way(side * mid) <= 0.5 ? hi : lo) = mid;
        }
        return hi;
      }
    }
    return -1.0;  // no crossing
  };
  const double lower = half_width(1.0), upper = half_width(-1.0);
  return lower < 0.0 || upper < 0.0 ? 0.0 : lower + upper;
}

}  // namespace sonarsynth
