// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/run_check.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/products/survey_products.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {

/// How to run a scene file (what `sonarsynth simulate` takes on its command line).
struct RunOptions {
  SimulationOverrides overrides;  ///< seed, range, samples, quality, threads; product flags
  /// Which products besides the XTF files, and how (mosaic pixel, format, creation options,
  /// waterfall size). `truth` is also off when the scene file turns truth off. The paths, the
  /// overwrite flag and the scene/seed metadata are set by run_simulation.
  SurveyProductOptions products;
  bool overwrite = false;  ///< replace an existing output directory (OutputDirectory rules)
  /// effective.yaml keeps the scene's relative file paths instead of making them absolute (a
  /// dataset item: its scene's mesh models are in the dataset directory, docs/dataset.md).
  bool relative_files = false;
  /// Called from the calling thread after each block of pings: (pings done, total).
  std::function<void(std::uint64_t, std::uint64_t)> progress;
  /// Called for each warning when it arises: the pre-run check's before rendering, the
  /// statistics' after it. Every warning is also in RunResult::warnings.
  std::function<void(const std::string&)> on_warning;
};

/// What a run produced and measured.
struct RunResult {
  RunPlan plan;                       ///< the pre-run estimates (check_simulation)
  std::vector<std::string> warnings;  ///< pre-run check, then saturation / no-seabed statistics
  /// XTF sample formats or sizes some common reader does not accept (docs/xtf.md §4).
  std::vector<std::string> compatibility_warnings;
  std::vector<std::string> notes;  ///< about the products (e.g. a decimated waterfall)
  /// Final paths: the XTF files, the products, then effective.yaml.
  std::vector<std::filesystem::path> files;
  std::vector<std::string> line_names;
  std::vector<RunStatistics::Line> line_statistics;  ///< per line, same order as line_names
  std::uint64_t total_pings = 0;
  AlongTrackChoice along_track;
  double along_track_tolerance_db = 0.0;  ///< of the configuration, dB
  double gain_db = 0.0;                   ///< quantiser gain applied, dB
  /// Wall time of each renderer stage, summed over the worker threads (thread time, not CPU:
  /// a thread waiting for a core counts), seconds.
  RenderTimings timings;
  /// Wall time from the first ping rendered to the last product written (rendering, XTF and
  /// products, which run in parallel), seconds.
  double run_s = 0.0;
  double products_s = 0.0;  ///< wall time of writing the mosaics (part of run_s), seconds
  /// Wall time of the boxes and chips (output.labels, after the run; not part of run_s), s.
  double labels_s = 0.0;
  double total_s = 0.0;  ///< wall time of the whole call, seconds
  double cpu_s = 0.0;    ///< CPU time of the process during the whole call, seconds
  /// CPU seconds of each output thread: "xtf", "mosaic", "waterfall", "truth" (accumulating
  /// pings) and "waterfall images", "truth images" (writing them); the rendering threads and
  /// the run statistics take the rest of cpu_s.
  std::vector<std::pair<std::string, double>> output_cpu_s;
};

/// Everything `sonarsynth simulate` does: loads `scene_path` with options.overrides, checks the
/// whole run before creating anything (check_simulation), renders the survey into an
/// OutputDirectory at `out_dir` (which may not contain the scene file) with one XTF file per line
/// (header fields from xtf_writer_options), the products and effective.yaml, and commits the
/// directory only when all is complete. Throws InputError / FormatError naming the file, key and
/// value; nothing is left at `out_dir` on failure.
RunResult run_simulation(const std::string& scene_path, const std::filesystem::path& out_dir,
                         const RunOptions& options = {});

}  // namespace sonarsynth
