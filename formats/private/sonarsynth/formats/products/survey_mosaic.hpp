// SPDX-License-Identifier: MIT
// The mosaic part of SurveyProducts (formats/products/survey_mosaic.cpp).
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "sonarsynth/formats/products/survey_products.hpp"

namespace sonarsynth::detail {

/// The survey mosaic sink of SurveyProducts: grids every ping into one mosaic (slant->ground
/// against the scene's bathymetry, in the scene's UTM frame); finish() writes mosaic.tif, its
/// display copy and the truth mosaics.
class SurveyMosaic : public PingSink {
 public:
  /// The files written (after finish()).
  virtual const std::vector<std::filesystem::path>& files() const = 0;
  /// Wall time of finish(), seconds.
  virtual double finish_s() const = 0;
};

/// The mosaic of the survey `lines` (their waypoints and the sonar's range give the extent),
/// written into `dir`; `options` must outlive it.
std::unique_ptr<SurveyMosaic> make_survey_mosaic(std::filesystem::path dir,
                                                 std::shared_ptr<const Scene> scene,
                                                 const SonarConfig& sonar,
                                                 const std::vector<SurveyLine>& lines,
                                                 const SurveyProductOptions& options);

}  // namespace sonarsynth::detail
