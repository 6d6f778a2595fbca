// SPDX-License-Identifier: MIT
#pragma once
// Speckle pre-filters proposed by the founding paper before feature detection.

#include <opencv2/core.hpp>
#include <string>

namespace sonarsynth::match {

enum class Prefilter { none, median, bilateral };

struct PrefilterOptions {
  int median_ksize = 5;                  ///< odd, >= 3
  int bilateral_diameter = 5;            ///< pixels, >= 1
  double bilateral_sigma_colour = 30.0;  ///< grey levels, > 0
  double bilateral_sigma_space = 3.0;    ///< pixels, > 0

  /// Throws InputError naming the option and the violated constraint.
  void validate() const;
};

/// "none", "median", "bilateral"; throws InputError naming `option` otherwise.
Prefilter parse_prefilter(const std::string& text, const char* option);
const char* prefilter_name(Prefilter filter);

/// The filtered copy of an 8-bit grey image (the image itself for none).
cv::Mat apply_prefilter(const cv::Mat& grey, Prefilter filter, const PrefilterOptions& options);

}  // namespace sonarsynth::match
