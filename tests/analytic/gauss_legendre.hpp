// SPDX-License-Identifier: MIT
// Composite Gauss–Legendre quadrature for the analytic references of the tests: written here,
// independent of the renderer's own quadrature (docs/physics.md §3).
#pragma once

#include <array>
#include <cstddef>

namespace sonarsynth::analytic {

/// Nodes and weights of the N-point Gauss–Legendre rule on [-1, 1] (N = 5 or 10).
template <std::size_t N>
struct GaussLegendreRule;

template <>
struct GaussLegendreRule<5> {
  static constexpr std::array<double, 5> x = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                              0.5384693101056831, 0.9061798459386640};
  static constexpr std::array<double, 5> w = {0.2369268850561891, 0.4786286704993665,
                                              0.5688888888888889, 0.4786286704993665,
                                              0.2369268850561891};
};

template <>
struct GaussLegendreRule<10> {
  static constexpr std::array<double, 10> x = {
      -0.9739065285171717, -0.8650633666889845, -0.6794095682990244, -0.4333953941292472,
      -0.1488743389816312, 0.1488743389816312,  0.4333953941292472,  0.6794095682990244,
      0.8650633666889845,  0.9739065285171717};
  static constexpr std::array<double, 10> w = {
      0.0666713443086881, 0.1494513491505806, 0.2190863625159820, 0.2692667193099963,
      0.2955242247147529, 0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
      0.1494513491505806, 0.0666713443086881};
};

/// The integral of f over [a, b]: `panels` equal panels, the N-point rule on each.
template <std::size_t N, class F>
double gauss_legendre(double a, double b, int panels, F&& f) {
  using Rule = GaussLegendreRule<N>;
  const double h = (b - a) / panels;
  double sum = 0.0;
  for (int k = 0; k < panels; ++k) {
    for (std::size_t g = 0; g < N; ++g) {
      sum += 0.5 * h * Rule::w[g] * f(a + h * (k + 0.5 + 0.5 * Rule::x[g]));
    }
  }
  return sum;
}

}  // namespace sonarsynth::analytic
