// SPDX-License-Identifier: MIT
// A threshold-free reference for the visible first return of a side-scan side
// (docs/conversion.md "The real Iver2 file"): the change point of a two-level model of the
// levels in dB, independent of the threshold-and-hold method of lib/bottom_track.cpp.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace bench {

/// Least-squares change point of a two-level model of x[b, e) (the maximum-likelihood one for
/// Gaussian levels of one variance): the c in [b + 2, e - 2] minimising the sum of squared
/// deviations from the mean of x[b, c) and of x[c, e); b when e - b < 4.
std::size_t two_level_change_point(const std::vector<double>& x, std::size_t b, std::size_t e);

/// Where the level of one side (samples NEAR -> FAR) leaves the water column. Levels in dB,
/// 20 log10(max(|sample|, 1e-6 x the largest |sample|)); the transmit pulse is the leading run
/// of samples above the side's median level and is skipped; the two-level change point is
/// fitted over the rest of the side, then again over the samples from the pulse's end to
/// window_samples past the last change point until it no longer moves (so that the seabed
/// part of the model is the window_samples after the onset, and the seabed's rise far from
/// nadir does not pull the change point up the slope). -1 if fewer than 8 samples follow the
/// pulse or window_samples < 2.
std::ptrdiff_t change_point_first_return(std::span<const float> side, std::size_t window_samples);

}  // namespace bench
