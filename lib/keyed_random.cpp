// SPDX-License-Identifier: MIT
#include "sonarsynth/keyed_random.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

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

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFpMin = DBL_MIN / DBL_EPSILON;

// ln Gamma(a), a > 0, without std::lgamma (which writes the global signgam: not thread-safe):
// tgamma below its overflow, else the Stirling series (Abramowitz & Stegun 6.1.40), whose first
// omitted term is < 1e-20 for a > 170.
double log_gamma(double a) {
  if (a < 170.0) return std::log(std::tgamma(a));
  const double r = 1.0 / a, r2 = r * r;
  return (a - 0.5) * std::log(a) - a + 0.91893853320467274178 +
         r * (1.0 / 12.0 - r2 * (1.0 / 360.0 - r2 * (1.0 / 1260.0 - r2 / 1680.0)));
}

// exp(-x + a ln x - ln Gamma(a)), the common prefactor of both expansions.
double prefactor(double a, double x, double lga) {
  return std::exp(-x + a * std::log(x) - lga);
}

// P(a, x) by its series, x < a + 1 (Numerical Recipes 3rd ed. §6.2, gser).
double gamma_p_series(double a, double x, double lga) {
  if (x <= 0.0) return 0.0;
  double ap = a, del = 1.0 / a, sum = del;
  for (int n = 0; n < 100000; ++n) {
    ap += 1.0;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * 1e-17) break;
  }
  return sum * prefactor(a, x, lga);
}

// Q(a, x) by its continued fraction, modified Lentz, x >= a + 1 (Numerical Recipes §6.2, gcf).
double gamma_q_fraction(double a, double x, double lga) {
  double b = x + 1.0 - a, c = 1.0 / kFpMin, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kFpMin) d = kFpMin;
    c = b + an / c;
    if (std::abs(c) < kFpMin) c = kFpMin;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) break;
  }
  return prefactor(a, x, lga) * h;
}

double gamma_p(double a, double x, double lga) {
  if (!(x > 0.0)) return 0.0;
  if (x == kInf) return 1.0;
  return x < a + 1.0 ? gamma_p_series(a, x, lga) : 1.0 - gamma_q_fraction(a, x, lga);
}
double gamma_q(double a, double x, double lga) {
  if (!(x > 0.0)) return 1.0;
  if (x == kInf) return 0.0;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x, lga) : gamma_q_fraction(a, x, lga);
}

// x with P(a, x) = p (Q(a, x) = q): Newton in u = ln x on the log of the smaller tail,
// h(u) = ln P(e^u) - ln p (or ln q - ln Q(e^u)), h'(u) = x f(x) / P (or / Q), f the Gamma(a)
// density; bracketed, bisection when a step leaves the bracket. ln P is nearly linear in u in
// the lower tail and ln Q nearly linear in x in the upper one, so few steps are needed.
double inverse_gamma(double a, double lga, double p, double q) {
  if (!(p > 0.0)) return 0.0;
  if (!(q > 0.0)) return kInf;
  const bool lower = p <= 0.5;
  const double target = std::log(lower ? p : q);
  // Starting point: the tails' leading terms, P ~ x^a / Gamma(a + 1), Q ~ x^(a-1) e^-x / Gamma(a).
  double u;
  if (lower) {
    u = (target + lga + std::log(a)) / a;
    u = std::min(u, std::log(a + 1.0));
  } else {
    double x = std::max(a, -target);
    for (int i = 0; i < 3; ++i) x = std::max(1e-3, -target + (a - 1.0) * std::log(x) - lga);
    u = std::log(std::max(x, 1e-300));
  }
  double lo = -kInf, hi = kInf;
  for (int iter = 0; iter < 400; ++iter) {
    const double x = std::exp(u);
    const double tail = lower ? gamma_p(a, x, lga) : gamma_q(a, x, lga);
    const double h = lower ? std::log(tail) - target : target - std::log(tail);
    if (h == 0.0) return x;
    if (h < 0.0) {
      lo = u;
    } else {
      hi = u;
    }
    const double dens_x = std::exp(a * u - x - lga);  // x f(x)
    // h' = x f / P (lower) or x f / Q (upper): both positive, so the step is -h / h'.
    double un = u - h * tail / dens_x;
    if (!(un > lo && un < hi)) {
      if (lo == -kInf) {
        un = u - 4.0;
      } else if (hi == kInf) {
        un = u + 1.0;
      } else {
        un = 0.5 * (lo + hi);
      }
    }
    if (std::abs(un - u) <= 1e-15 * std::max(1.0, std::abs(u)) || hi - lo <= 1e-15) {
      return std::exp(un);
    }
    u = un;
  }
  return std::exp(u);
}

}  // namespace

double regularized_gamma_p(double a, double x) {
  return gamma_p(a, x, log_gamma(a));
}
double regularized_gamma_q(double a, double x) {
  return gamma_q(a, x, log_gamma(a));
}
double inverse_regularized_gamma(double a, double p, double q) {
  return inverse_gamma(a, log_gamma(a), p, q);
}

UnitGammaTable::UnitGammaTable(double shape) : shape_(shape), lgamma_shape_(0.0) {
  if (!(shape > 0.0 && shape <= kMaxShape)) {
    throw std::invalid_argument("UnitGammaTable: shape = " + std::to_string(shape) +
                                ". Violated constraint: 0 < shape <= " + std::to_string(kMaxShape));
  }
  const double a = shape;
  lgamma_shape_ = log_gamma(a);
  const double lga1 = lgamma_shape_ + std::log(a);  // ln Gamma(a + 1)
  const double m = static_cast<double>(kBins);
  // Quantiles (Gamma(a, 1) scale) at the bin edges k / kBins, k = 1 .. kBins - 1.
  std::vector<double> edge(kBins + 1, 0.0);
  for (std::size_t k = 1; k < kBins; ++k) {
    edge[k] = inverse_gamma(a, lgamma_shape_, static_cast<double>(k) / m,
                            static_cast<double>(kBins - k) / m);
  }
  bins_.assign(kBins, Bin{0.0, 0.0, 0.0});
  for (std::size_t k = 1; k + 1 < kBins; ++k) {
    const double x0 = edge[k], x1 = edge[k + 1];
    // E[X / a; x0 < X < x1] = P(a + 1, x1) - P(a + 1, x0), from the smaller tail.
    const double mass = x0 < a + 1.0 ? gamma_p(a + 1.0, x1, lga1) - gamma_p(a + 1.0, x0, lga1)
                                     : gamma_q(a + 1.0, x0, lga1) - gamma_q(a + 1.0, x1, lga1);
    const double mean = m * mass;  // conditional mean of X / a in the bin
    Bin& b = bins_[k];
    b.x = x0 / a;
    b.d = (x1 - x0) / a;
    // value(frac) = x + d frac + c frac (1 - frac) has mean x + d / 2 + c / 6 over frac.
    b.c = 6.0 * (mean - b.x - 0.5 * b.d);
    // Monotone as long as |c| <= d (holds by a wide margin except for extreme shapes).
    b.c = std::clamp(b.c, -b.d, b.d);
  }
  bins_float_.assign(3 * kBins, 0.0f);
  for (std::size_t k = 0; k < kBins; ++k) {
    bins_float_[k] = static_cast<float>(bins_[k].x);
    bins_float_[kBins + k] = static_cast<float>(bins_[k].d);
    bins_float_[2 * kBins + k] = static_cast<float>(bins_[k].c);
  }
}

double UnitGammaTable::exact_quantile(double p, double q) const {
  return inverse_gamma(shape_, lgamma_shape_, p, q) / shape_;
}

double UnitGammaTable::tail(std::uint64_t k, std::uint64_t m) const {
  // p = (k + frac) / kBins with frac = (m + 1/2) 2^-52: both tails exactly representable.
  const double scale = 0x1.0p-52 / static_cast<double>(kBins);
  if (k == 0) {
    const double p = (static_cast<double>(m) + 0.5) * scale;
    return exact_quantile(p, 1.0 - p);
  }
  const double q = (static_cast<double>((std::uint64_t{1} << 52) - m) - 0.5) * scale;
  return exact_quantile(1.0 - q, q);
}

double NormalTable::density(double x) {
  return 0.39894228040143267794 * std::exp(-0.5 * x * x);
}
double NormalTable::upper_tail(double x) {
  return 0.5 * std::erfc(x * 0.70710678118654752440);
}

NormalTable::NormalTable() : table_(kCells), edge_(kCells + 1) {
  const double cells = static_cast<double>(kCells);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // Upper edges x_k with Q(x_k) = k / 2^16, k = 2^15 .. 1 (x from 0 up), by Newton from the
  // previous edge: Q is convex and decreasing on x >= 0, so Newton from the left of the root
  // converges monotonically; the lower half by symmetry.
  const std::size_t half = kCells / 2;
  edge_[half] = 0.0;
  double x = 0.0;
  for (std::size_t k = half - 1; k >= 1; --k) {
    const double p = static_cast<double>(k) / cells;  // exact
    for (int iter = 0; iter < 100; ++iter) {
      const double step = (upper_tail(x) - p) / density(x);
      x += step;
      if (!(std::abs(step) > 1e-15 * x)) break;
    }
    edge_[kCells - k] = x;
    edge_[k] = -x;
  }
  edge_[0] = -kInfinity;
  edge_[kCells] = kInfinity;
  // Conditional means of the upper half's cells (density 0 at an infinite edge); the lower half
  // mirrors them.
  std::vector<double> mean(kCells);
  double second = 0.0;
  for (std::size_t k = half; k < kCells; ++k) {
    const double b = edge_[k + 1];
    const double m = cells * (density(edge_[k]) - (std::isinf(b) ? 0.0 : density(b)));
    mean[k] = m;
    mean[kCells - 1 - k] = -m;
    second += 2.0 * m * m;
  }
  scale_ = 1.0 / std::sqrt(second / cells);
  for (std::size_t k = 0; k < kCells; ++k) table_[k] = static_cast<float>(mean[k] * scale_);
}

const NormalTable& NormalTable::get() {
  static const NormalTable table;
  return table;
}

const UnitGammaTable& UnitGammaTable::get(double shape) {
  static std::mutex mutex;
  static std::map<double, std::unique_ptr<UnitGammaTable>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[shape];
  if (!slot) slot = std::make_unique<UnitGammaTable>(shape);
  return *slot;
}

}  // namespace sonarsynth
