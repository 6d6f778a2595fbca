// SPDX-License-Identifier: MIT
#include "sonarsynth/match/prefilter.hpp"

#include <opencv2/imgproc.hpp>

#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth::match {

void PrefilterOptions::validate() const {
  if (median_ksize < 3 || median_ksize % 2 == 0) {
    throw InputError("median kernel size = " + std::to_string(median_ksize) +
                     ". Violated constraint: odd and >= 3");
  }
  if (bilateral_diameter < 1) {
    throw InputError("bilateral diameter = " + std::to_string(bilateral_diameter) +
                     ". Violated constraint: >= 1 pixel");
  }
  if (!(bilateral_sigma_colour > 0) || !(bilateral_sigma_space > 0)) {
    throw InputError("bilateral sigmas = " + std::to_string(bilateral_sigma_colour) + ", " +
                     std::to_string(bilateral_sigma_space) + ". Violated constraint: both > 0");
  }
}

constexpr EnumName<Prefilter> kPrefilterNames[] = {
    {Prefilter::none, "none"}, {Prefilter::median, "median"}, {Prefilter::bilateral, "bilateral"}};

Prefilter parse_prefilter(const std::string& text, const char* option) {
  return parse_enum(kPrefilterNames, text, std::string("--") + option);
}

const char* prefilter_name(Prefilter filter) {
  return enum_name(kPrefilterNames, filter);
}

cv::Mat apply_prefilter(const cv::Mat& grey, Prefilter filter, const PrefilterOptions& options) {
  options.validate();
  if (grey.type() != CV_8UC1) throw InputError("pre-filter: the image must be 8-bit grey");
  cv::Mat out;
  switch (filter) {
    case Prefilter::none:
      return grey;
    case Prefilter::median:
      cv::medianBlur(grey, out, options.median_ksize);
      return out;
    case Prefilter::bilateral:
      cv::bilateralFilter(grey, out, options.bilateral_diameter, options.bilateral_sigma_colour,
                          options.bilateral_sigma_space);
      return out;
  }
  return grey;
}

}  // namespace sonarsynth::match
