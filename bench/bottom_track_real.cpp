// SPDX-License-Identifier: MIT
// Bottom tracking and gain normalisation on a real file (docs/conversion.md).
// Usage: bottom_track_real FILE.xtf|.jsf [REFERENCE_MEDIAN_PINGS [CHANGE_WINDOW_M]]
// 1. Agreement of the tracked first return (BottomTracker) with the "visible first return",
//    per side and per ping (the tracked altitude against the mean of the sides' returns), for
//    two references: the realism measures' detector (bench/realism_stats, docs/realism.md
//    measure 4: a running-median level detector 20 dB below the seabed level with a hold;
//    optionally median-filtered along track over REFERENCE_MEDIAN_PINGS) and the threshold-free
//    change point of bench/first_return_change_point (seabed part CHANGE_WINDOW_M, 1 m).
// 2. The band beside nadir: pings slant-range corrected on a flat bottom with an altitude,
//    levels 20 log10(sample) averaged per ground-range bin; the band is ground range
//    [0, kBandM) and the reference [kRefBeginM, kRefEndM); reported as band - reference, in dB,
//    with the header altitude and no gain ("before"), with the auto altitude, and with the auto
//    altitude and the angle gain normalisation ("after").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "first_return_change_point.hpp"
#include "realism_stats.hpp"
#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"

namespace rs = bench::realism;
using namespace sonarsynth;

namespace {

constexpr double kBandM = 1.0;
constexpr double kRefBeginM = 3.0;
constexpr double kRefEndM = 15.0;
constexpr double kBinM = 0.25;
// Reference 2: the length of seabed after the onset that its two-level fit sees.
double kChangeWindowM = 1.0;
std::size_t kRefMedianPings = 1;

struct Levels {
  std::vector<double> sum, n;
  void add(double g, double v) {
    if (!(v > 0.0)) return;
    const auto b = static_cast<std::size_t>(g / kBinM);
    if (b >= sum.size()) {
      sum.resize(b + 1, 0.0);
      n.resize(b + 1, 0.0);
    }
    sum[b] += 20.0 * std::log10(v);
    n[b] += 1.0;
  }
  double mean(double g0, double g1) const {
    double s = 0.0, c = 0.0;
    for (std::size_t b = 0; b < sum.size(); ++b) {
      const double g = (static_cast<double>(b) + 0.5) * kBinM;
      if (g < g0 || g >= g1) continue;
      s += sum[b];
      c += n[b];
    }
    return c > 0.0 ? s / c : std::nan("");
  }
};

/// The visible first return seen along the line: each ping's detection replaced by the median
/// of the detections of the `window` pings centred on it (1 = the per-ping detections).
std::vector<rs::FirstReturn> smoothed(std::vector<rs::FirstReturn> fr, std::size_t window) {
  std::vector<rs::FirstReturn> out = fr;
  const std::size_t half = window / 2;
  std::vector<double> w;
  for (std::size_t k = 0; k < fr.size(); ++k) {
    w.clear();
    for (std::size_t j = k >= half ? k - half : 0; j < std::min(fr.size(), k + half + 1); ++j) {
      if (fr[j].found) w.push_back(fr[j].range_m);
    }
    if (w.empty()) continue;
    std::sort(w.begin(), w.end());
    out[k].found = true;
    out[k].range_m = w[w.size() / 2];
  }
  return out;
}

// The side-scan pings of a file (XTF or JSF), those with samples.
std::vector<rs::Ping> read_pings(const std::string& path) {
  std::vector<rs::Ping> pings;
  const auto src = SideScanSource::open(path);
  SideScanRecord rec;
  while (src->next(rec)) {
    const SonarPing& s = rec.sonar;
    if (s.port.empty() && s.starboard.empty()) continue;
    rs::Ping p;
    p.port = s.port;
    p.starboard = s.starboard;
    p.altitude_m = s.altitude_m;
    p.slant_range_m = s.slant_range_m;
    pings.push_back(std::move(p));
  }
  return pings;
}

// The two references' first-return range per side and ping, refs[reference][side] (NaN where
// it has none): 1 realism measure 4 smoothed along track, 2 the change point of `window`
// samples.
void reference_ranges(const std::vector<rs::Ping>& pings, std::size_t window,
                      std::vector<double> (&refs)[2][2]) {
  const rs::Options ro;
  const auto ref_p = smoothed(rs::first_returns(pings, rs::Side::kPort, ro), kRefMedianPings);
  const auto ref_s = smoothed(rs::first_returns(pings, rs::Side::kStarboard, ro), kRefMedianPings);
  for (int side = 0; side < 2; ++side) {
    const auto& old = side == 0 ? ref_p : ref_s;
    for (std::size_t k = 0; k < pings.size(); ++k) {
      refs[0][side].push_back(old[k].found ? old[k].range_m : std::nan(""));
      const std::vector<float>& v = side == 0 ? pings[k].port : pings[k].starboard;
      const std::ptrdiff_t c = v.empty() ? -1 : bench::change_point_first_return(v, window);
      refs[1][side].push_back(c < 0 ? std::nan("")
                                    : (static_cast<double>(c) + 0.5) * pings[k].slant_range_m /
                                          static_cast<double>(v.size()));
    }
  }
}

// Prints the agreement of the tracker (per side, and the ping altitude alt) with reference r.
void print_agreement(const std::vector<rs::Ping>& pings, const std::vector<double> (&refs)[2][2],
                     int r, const std::vector<double> (&track_side)[2],
                     const std::vector<double>& alt, double dr) {
  for (int side = 0; side < 2; ++side) {
    std::size_t n = 0, ok = 0;
    for (std::size_t k = 0; k < pings.size(); ++k) {
      const double ref = refs[r][side][k];
      if (!std::isfinite(ref)) continue;
      ++n;
      if (std::abs(track_side[side][k] - ref) <= 2.0 * dr + 1e-9) ++ok;
      if (std::getenv("BT_DEBUG")) {
        std::printf("dbg %d %d %zu %.1f %.1f\n", r, side, k, track_side[side][k] / dr, ref / dr);
      }
    }
    std::printf("  %s: %zu of %zu pings (%.1f %%)\n", side == 0 ? "port" : "starboard", ok, n,
                100.0 * static_cast<double>(ok) / static_cast<double>(n));
  }
  std::size_t ping_n = 0, ping_ok = 0, header_near = 0;
  for (std::size_t k = 0; k < pings.size(); ++k) {
    double sum = 0.0, c = 0.0;
    for (int side = 0; side < 2; ++side) {
      if (std::isfinite(refs[r][side][k])) {
        sum += refs[r][side][k];
        c += 1.0;
      }
    }
    if (c == 0.0) continue;
    ++ping_n;
    if (std::abs(alt[k] - sum / c) <= 2.0 * dr + 1e-9) ++ping_ok;
    if (std::abs(pings[k].altitude_m - sum / c) <= 2.0 * dr) ++header_near;
  }
  std::printf("  ping altitude (mean of sides): %zu of %zu pings (%.1f %%)\n", ping_ok, ping_n,
              100.0 * static_cast<double>(ping_ok) / static_cast<double>(ping_n));
  std::printf("  header altitude within 2 samples of it: %zu of %zu pings\n", header_near, ping_n);
}

// Prints the quantiles of header altitude - tracked altitude alt.
void print_header_minus_track(const std::vector<rs::Ping>& pings, const std::vector<double>& alt) {
  std::vector<double> header_minus_track;
  for (std::size_t k = 0; k < pings.size(); ++k) {
    if (pings[k].altitude_m > 0.0) header_minus_track.push_back(pings[k].altitude_m - alt[k]);
  }
  std::sort(header_minus_track.begin(), header_minus_track.end());
  if (!header_minus_track.empty()) {
    const auto q = [&](double f) {
      return header_minus_track[static_cast<std::size_t>(
          f * static_cast<double>(header_minus_track.size() - 1))];
    };
    std::printf("header - tracked altitude: median %.3f m, 5 %% %.3f m, 95 %% %.3f m\n", q(0.5),
                q(0.05), q(0.95));
  }
}

// Prints the band levels before and after the across-track gain normalisation (pass 0: header
// altitude, no gain; 1: tracked altitude, no gain; 2: tracked altitude, angle gain).
void print_band_levels(const std::vector<rs::Ping>& pings, const std::vector<double>& alt,
                       double dr) {
  for (int pass = 0; pass < 3; ++pass) {
    const AltitudeSource source = pass == 0 ? AltitudeSource::kHeader : AltitudeSource::kAuto;
    GainNormaliser gain(pass < 2 ? GainNormalisation::kOff : GainNormalisation::kAngle);
    std::size_t tracked = 0;
    std::vector<double> chosen(pings.size());
    for (std::size_t k = 0; k < pings.size(); ++k) {
      const AltitudeChoice a = choose_altitude(source, pings[k].altitude_m, alt[k], dr);
      chosen[k] = a.altitude_m;
      tracked += a.tracked ? 1 : 0;
      gain.add_ping(pings[k].port, pings[k].starboard, pings[k].slant_range_m, a.altitude_m);
    }
    gain.finish();
    Levels lv;
    for (std::size_t k = 0; k < pings.size(); ++k) {
      const double h = chosen[k];
      if (!(h > 0.0)) continue;
      std::vector<float> p = pings[k].port, s = pings[k].starboard;
      gain.apply(p, s, pings[k].slant_range_m, h);
      for (const std::vector<float>* side : {&p, &s}) {
        const double d = pings[k].slant_range_m / static_cast<double>(side->size());
        for (std::size_t i = 0; i < side->size(); ++i) {
          const double r = (static_cast<double>(i) + 0.5) * d;
          if (r <= h) continue;
          lv.add(std::sqrt(r * r - h * h), (*side)[i]);
        }
      }
    }
    const double band = lv.mean(0.0, kBandM), ref = lv.mean(kRefBeginM, kRefEndM);
    std::printf(
        "%s (altitude %s, %zu pings tracked; gain %s): band [0, %.1f) m %.1f dB, reference "
        "[%.0f, %.0f) m %.1f dB: band - reference %+.1f dB\n",
        pass == 0 ? "before" : "after", to_string(source), tracked, to_string(gain.mode()), kBandM,
        band, kRefBeginM, kRefEndM, ref, band - ref);
    std::printf("  profile (dB per 0.5 m of ground range from nadir):");
    for (double g = 0.0; g < 20.0; g += 0.5) std::printf(" %.1f", lv.mean(g, g + 0.5));
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2 || argc > 4) {
    std::fprintf(
        stderr,
        "usage: bottom_track_real FILE.xtf|.jsf [REFERENCE_MEDIAN_PINGS [CHANGE_WINDOW_M]]\n");
    return 2;
  }
  if (argc == 4) kChangeWindowM = std::atof(argv[3]);
  if (!(kChangeWindowM > 0.0)) throw InputError("CHANGE_WINDOW_M must be > 0");
  if (argc >= 3) kRefMedianPings = static_cast<std::size_t>(std::atoi(argv[2]));
  const std::string path = argv[1];
  const std::vector<rs::Ping> pings = read_pings(path);
  if (pings.empty()) throw InputError(path + ": no side-scan ping");
  BottomTracker tracker;
  for (const rs::Ping& p : pings) tracker.add_ping(p.port, p.starboard, p.slant_range_m);
  const std::vector<double> alt = tracker.altitudes_m();
  const double dr = pings[0].slant_range_m / static_cast<double>(pings[0].port.size());
  const auto window = static_cast<std::size_t>(std::lround(kChangeWindowM / dr));
  std::vector<double> refs[2][2];
  reference_ranges(pings, window, refs);
  const std::vector<double> track_side[2] = {tracker.side_ranges_m(0), tracker.side_ranges_m(1)};
  std::printf("file %s: %zu pings, sample %.4f m\n", path.c_str(), pings.size(), dr);
  for (int r = 0; r < 2; ++r) {
    if (r == 0) {
      std::printf(
          "agreement within 2 samples of the visible first return, reference 1: realism measure "
          "4 (threshold 20 dB below the near seabed), along-track median of %zu pings:\n",
          kRefMedianPings);
    } else {
      std::printf(
          "reference 2: change point of a two-level model of the dB levels, seabed part %zu "
          "samples (%.2f m):\n",
          window, kChangeWindowM);
    }
    print_agreement(pings, refs, r, track_side, alt, dr);
  }
  print_header_minus_track(pings, alt);
  print_band_levels(pings, alt, dr);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bottom_track_real: %s\n", e.what());
  return 1;
}
