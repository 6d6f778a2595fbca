// SPDX-License-Identifier: MIT
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/mosaic.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace geo_truth {
class GeoTruthWriter;
}
namespace detail {
class SurveyMosaic;
}

/// What `simulate` derives from the rendered pings besides the XTF files.
struct SurveyProductOptions {
  bool mosaic = true;      ///< mosaic.tif (+ mosaic_rgb.tif, truth_mosaic.tif)
  bool waterfalls = true;  ///< <line>_waterfall.png per line
  bool truth = true;       ///< <line>_truth.tif per line and truth_mosaic.tif
  double mosaic_pixel_m = kDefaultMosaicPixelM;  ///< > 0
  /// Largest waterfall image (pixels); a longer line is decimated along track to fit.
  std::size_t waterfall_max_pixels = WaterfallOptions{}.max_pixels;
  MosaicOptions mosaic_options;
  /// Across-track gain normalisation of the mosaic (docs/conversion.md, the `mosaic` command's
  /// --gain-normalisation): off grids each ping as it comes; range or angle keep the pings in a
  /// temporary file in the output directory (8 bytes a sample) while the statistics of the whole
  /// survey accumulate, and grid them, normalised, in finish().
  GainNormalisation gain_normalisation = GainNormalisation::kOff;
  /// Mosaic accumulators held in memory while the survey runs; the tiles used least recently
  /// beyond this go to a temporary file in the output directory (MosaicGrid::spill_to), so that
  /// memory does not grow with the survey. 0 = all in memory.
  std::size_t mosaic_resident_bytes = std::size_t{16} << 20;
  MosaicWriteOptions write_options;  ///< format, creation options (paths are set here)
  /// > 0: the waterfalls and mosaic_rgb show value / this linearly (output.display: linear, the
  /// samples' full scale); 0: a dB window (percentiles).
  double display_linear_full_scale = 0.0;
  /// Given (and display_linear_full_scale 0): the waterfalls and mosaic_rgb map 10 log10(value)
  /// from first (0) to second (1), one window for every image (output.display_window_db).
  std::optional<std::pair<double, double>> display_window_db;
  /// Optional taps on each line's waterfall image rows and label rows as they are written (the
  /// label sets of docs/labels.md, made in the same pass): called with the line's name on the
  /// thread that writes the line; the taps run on that thread.
  std::function<Waterfall::RowTap(const std::string& line)> waterfall_rows;
  std::function<TruthWaterfall::LabelRowTap(const std::string& line)> label_rows;
  /// true: a finished line's images are written on a thread of their own while the next line
  /// accumulates; false: on the calling thread (a one-thread run: one core). Same files.
  bool background_images = true;
  /// The grazing angle band of `<line>_truth.tif` (output.truth_grazing, docs/labels.md).
  TruthGrazing truth_grazing = TruthGrazing::hundredths;
  /// Called once, on the mosaic's thread, when the mosaic has gridded the last ping (the start
  /// of its finish()): from then on no product reads the scene's bathymetry. run_simulation,
  /// which owns the scene and has rendered every ping by then, frees the bathymetry grid there,
  /// so that the mosaic files are written without it (the run's peak memory). Not called
  /// without a mosaic, or when the run is aborted.
  std::function<void()> after_last_bathymetry_use;
  void validate() const;
};

/// The `simulate` options that give `o`'s products, for the options that differ from
/// SurveyProductOptions{}: "--no-mosaic", "--no-waterfall", "--no-truth", "--res X", "--of GTiff",
/// "--co KEY=VALUE" (one per creation option), "--waterfall-max-pixels N", in that order.
/// effective.yaml records them (they are not scene settings), whichever front end made the run.
std::vector<std::string> product_option_flags(const SurveyProductOptions& o);

/// A ping sink that grids every ping into one survey mosaic (slant->ground against the scene's
/// own bathymetry, in the scene's UTM frame) and collects a waterfall and a truth waterfall per
/// line, written when the line ends; finish() writes the mosaics. Files go to `dir`; abort()
/// drops the accumulators (files already written stay: the caller's OutputDirectory discards
/// them).
///
/// The three products are independent sinks (parts()): a caller may feed each on a thread of its
/// own (run_simulation does) instead of calling this sink, with the same files. A line's images
/// are written on a further thread while the next line accumulates (one line at a time); their
/// errors surface at the next end_line() or finish().
class SurveyProducts : public PingSink {
 public:
  /// Shares ownership of `scene` (not null). `lines` (local frame) and the sonar's range give
  /// the mosaic extent.
  SurveyProducts(std::filesystem::path dir, std::shared_ptr<const Scene> scene,
                 const SonarConfig& sonar, const std::vector<SurveyLine>& lines,
                 SurveyProductOptions options);
  ~SurveyProducts() override;
  SurveyProducts(const SurveyProducts&) = delete;
  SurveyProducts& operator=(const SurveyProducts&) = delete;
  void begin(const RunDescription& run) override;
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& ping) override;
  void end_line(std::size_t line) override;
  /// Writes the mosaic files (the Simulator calls it once, after the run).
  void finish() override;
  void abort() noexcept override;

  /// The enabled products as independent sinks, with a name: "mosaic", "waterfall", "truth",
  /// "vectors" (with the truth: targets.geojson, tracks.geojson, coverage.geojson).
  /// Each receives every call in order; together they do what this sink does.
  std::vector<std::pair<std::string, PingSink*>> parts();
  /// Wall time of writing the mosaic files, seconds.
  double finish_s() const;
  /// Thread CPU seconds of the line images written in the background: "waterfall images",
  /// "truth images" (after finish()).
  std::vector<std::pair<std::string, double>> writer_cpu_s() const;
  /// Files written (after finish()): per line its waterfall then its truth waterfall, then the
  /// mosaic files, then the truth vectors.
  std::vector<std::filesystem::path> files() const;
  /// What the user should know about the products (e.g. a waterfall decimated along track).
  std::vector<std::string> notes() const;

 private:
  class LinePart;
  class WaterfallPart;
  class TruthPart;
  SurveyProductOptions options_;
  std::unique_ptr<detail::SurveyMosaic> mosaic_;
  std::unique_ptr<LinePart> waterfall_;
  std::unique_ptr<LinePart> truth_;
  std::unique_ptr<geo_truth::GeoTruthWriter> vectors_;
};

}  // namespace sonarsynth
