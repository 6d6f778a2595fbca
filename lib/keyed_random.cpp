// SPDX-License-Identifier: MIT
#include "sonarsynth/keyed_random.hpp"

#include <cmath>

namespace sonarsynth {

double keyed_gamma(double shape, std::uint64_t seed, std::uint64_t key, std::uint64_t stream) {
  // Marsaglia & Tsang (2000), ACM TOMS 26(3):363-372.
  double boost = 1.0;
  if (shape < 1.0) {
    // Gamma(a) = Gamma(a + 1) U^(1/a) (same paper, section 6).
    const double u = uniform_open0_from_bits(keyed_hash(seed, key, stream));
    boost = std::pow(u, 1.0 / shape);
    shape += 1.0;
    stream += 1;
  }
  const double d = shape - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  for (std::uint64_t attempt = 0;; ++attempt) {
    const std::uint64_t s = stream + 3 * attempt;
    const NormalPair n = keyed_normal_pair(seed, key, s);
    const double x = n.n1;
    double v = 1.0 + c * x;
    if (v <= 0.0) continue;
    v = v * v * v;
    const double u = uniform_open0_from_bits(keyed_hash(seed, key, s + 2));
    const double x2 = x * x;
    if (u < 1.0 - 0.0331 * x2 * x2 || std::log(u) < 0.5 * x2 + d * (1.0 - v + std::log(v))) {
      return d * v * boost;
    }
  }
}

}  // namespace sonarsynth
