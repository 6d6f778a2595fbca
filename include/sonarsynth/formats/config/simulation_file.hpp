// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/simulator.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth {

/// Command-line overrides of common scene-file settings (GDAL-style: the file stays the
/// reference, the overrides are recorded in the effective configuration).
struct SimulationOverrides {
  std::optional<std::uint64_t> seed;
  std::optional<double> range_m;
  std::optional<std::size_t> samples;
  std::optional<unsigned> threads;
  /// A QualityConfig preset (QualityConfig::apply_preset): "fast" (1 Gauss point, 8 object
  /// segments, 1 along-track plane), "default", "high" (4 grid subdivisions, 3 Gauss points,
  /// the automatic along-track plane count with a 0.25 dB tolerance).
  std::optional<std::string> quality;
};

/// A command-line flag of `simulate` that overrides scene-file options ("range": --range), from
/// the option table that declares the options (docs/scene-format.md, "Defaults and
/// declarations").
struct OverrideFlag {
  std::string name;  ///< without the dashes: "seed", "range", "samples", "quality"
  std::string help;  ///< one line for the CLI's help
};
/// Every override flag, in the order of the options they override.
std::vector<OverrideFlag> override_flags();
/// Sets the override `name` (an OverrideFlag's) in `overrides` from its command-line text;
/// throws InputError naming the flag and the text if it is not a value of the flag's type (the
/// bounds are checked when the scene is loaded), std::invalid_argument for an unknown name.
void set_override(SimulationOverrides& overrides, const std::string& name, const std::string& text);

/// Bounds on the work and output of one run, checked before rendering (`limits:` in the scene
/// file, docs/scene-format.md).
struct RunLimits {
  std::uint64_t max_pings = 2'000'000;
  double max_output_gb = 50.0;  ///< XTF files and products together, 10^9 bytes
  double max_memory_gb = 8.0;   ///< renderer workspaces and mosaic accumulators, 10^9 bytes
};

/// output.labels: machine-learning labels besides the truth rasters (docs/labels.md). The
/// class and instance rasters come with the truth; these are off by default.
struct LabelOutput {
  /// The instance mask of each COCO annotation: COCO uncompressed RLE, polygons, or none.
  enum class Segmentation { rle, polygon, none };
  /// The chip images: the image's colours (colormap), or one 8-bit grey band of the display value.
  enum class ChipColor { colormap, grey };
  /// Raw-sample chips beside the images: none, or the sample values as uint16 or float32.
  enum class ChipSamples { none, u16, f32 };
  bool coco = false;  ///< waterfalls.coco.json, mosaic.coco.json (and chips/coco.json)
  bool yolo = false;  ///< yolo/ (Ultralytics layout: data.yaml, images/, labels/; and chips/)
  bool voc = false;   ///< voc/Annotations/<image>.xml (and chips/voc/Annotations/<chip>.xml)
  Segmentation segmentation = Segmentation::rle;
  ChipColor chip_color = ChipColor::colormap;
  ChipSamples chip_samples = ChipSamples::none;
  bool chips = false;                ///< chips/images, chips/masks (and their boxes as asked above)
  std::size_t chip_size_px = 256;    ///< chip side, pixels
  std::size_t chip_stride_px = 256;  ///< step between chips, pixels
  /// Chips with a larger fraction of nodata pixels are skipped (all-nodata ones always).
  double chip_max_nodata_fraction = 0.5;
  bool any() const { return coco || yolo || voc || chips; }
};

/// output.mosaic: how `simulate` processes its mosaic (docs/scene-format.md), as survey software
/// does; raw + off is the plain gridding of every seabed sample.
struct MosaicProcessing {
  /// blank: the first return (the slant ranges of the pulse echoed by the seabed below the
  /// sensor) is not gridded and the nadir gap stays nodata where no other line covers it; fill:
  /// the same, the gap then taking the first sample beyond it; raw: every seabed sample gridded,
  /// the gap filled with the first one (the `mosaic` command's default).
  enum class Nadir : std::uint8_t { blank, fill, raw };
  Nadir nadir = Nadir::blank;
  /// Across-track gain normalisation over the whole survey (docs/conversion.md).
  GainNormalisation gain = GainNormalisation::kAngle;
};

/// What `sonarsynth simulate` runs: the scene, the simulation settings and the survey. A key left
/// out of the scene file keeps the default of its struct member (formats/config/option_table.cpp
/// declares each key once: its unit, bounds and member).
struct SimulationSetup {
  Scene scene;
  SimulationConfig config{};
  std::vector<SurveyLine> lines{};
  VehicleConfig vehicle{};
  UtcTime start_time = std::chrono::sys_days(std::chrono::year(2026) / 1 / 1);  ///< 2026-01-01
  std::string sample_format = "u16";  ///< XTF sample format: u16, u8 or f32
  /// The reference altitude for the global calibration (survey altitude, or depth above the
  /// mean seabed in constant-depth mode), metres.
  double reference_altitude_m = 10.0;
  RunLimits limits{};
  /// output.allow_more_than_8192_samples: write more samples per channel than common XTF
  /// readers accept.
  bool allow_more_than_8192_samples = false;
  /// output.bag_truth: the mcap and rosbag files also carry each ping's per-sample truth on
  /// topics of their own (docs/robotics.md, "Truth topics"). Needs output.truth: true and a bag
  /// format in output.formats (bag_truth_violation).
  bool bag_truth = false;
  /// output.formats: the sonar formats `simulate` writes, one `<line><extension>` file per line
  /// and format (names of sonar_formats(), e.g. "xtf", "jsf"; docs/scene-format.md). The files
  /// are written in the order of the format list whatever the order here. output.jsf: true is
  /// an alias of adding "jsf".
  std::vector<std::string> output_formats{"xtf"};
  /// True if `name` is in output_formats.
  bool writes_format(std::string_view name) const;
  /// output.display: the waterfalls and mosaic_rgb show sample / full scale linearly (the
  /// founding paper's grey level, docs/paper-model.md) instead of a dB window.
  bool display_linear = false;
  /// output.truth_grazing: the grazing angle band of `<line>_truth.tif` (docs/labels.md).
  TruthGrazing truth_grazing = TruthGrazing::hundredths;
  /// output.labels (docs/labels.md).
  LabelOutput labels{};
  /// output.display_window_db: [lo, hi], 10 log10(sample / full scale) mapped to the darkest and
  /// brightest display level of every waterfall, mosaic_rgb and chip (docs/labels.md, "One
  /// display scale"); not given: each image's own 1st-99th percentile window.
  std::optional<std::pair<double, double>> display_window_db{};
  /// output.mosaic (docs/scene-format.md).
  MosaicProcessing mosaic_processing{};
  /// Where the range came from, for messages: "sonar.range_m" or "--range".
  std::string range_key = "sonar.range_m";
  Survey make_survey() const;
};

/// Loads a scene file with its survey, sonar, render, noise and output sections (format:
/// docs/scene-format.md) and applies the overrides. Throws InputError / FormatError naming the
/// file, the key and the bad value.
SimulationSetup load_simulation(const std::string& path, const SimulationOverrides& overrides = {});
/// As load_simulation(), from YAML text in memory: `name` stands for the file in messages,
/// relative file paths are relative to `base_dir`.
SimulationSetup load_simulation_from_string(const std::string& yaml_text, const std::string& name,
                                            const std::filesystem::path& base_dir,
                                            const SimulationOverrides& overrides = {});

/// Throws InputError "<name>: survey line '<line>' waypoint <k> = (x, y) m ..." unless every
/// waypoint of `line` (local frame, metres) is finite and within 1e6 m of the bathymetry grid's
/// centre along each axis: the rule of a scene file's waypoints, for lines built in code.
void check_survey_line(const Scene& scene, const SurveyLine& line, const std::string& name);

/// The constraints that tie several keys together, each as "the constraint violated" or nothing:
/// a scene file is checked against them as it is read (its messages name the file and line),
/// a setup built in code by check_cross_keys() before it renders.
/// - sonar.ping_period_s (when > 0) at least the two-way travel time to the range;
std::optional<std::string> ping_period_violation(const SimulationSetup& setup);
/// - sensor.ring_down_m at most a tenth of the range (the library caps a default one there);
std::optional<std::string> ring_down_violation(const SimulationSetup& setup);
/// - sonar.samples at most 8192 unless output.allow_more_than_8192_samples.
std::optional<std::string> sample_count_violation(const SimulationSetup& setup);

/// - output.bag_truth: true only with output.truth: true and mcap or rosbag in output.formats.
std::optional<std::string> bag_truth_violation(const SimulationSetup& setup);

/// Throws InputError "<name>: <key> = <value>. Violated constraint: ..." for the first of the
/// constraints above that `setup` violates; the ring-down is checked when it is not the default
/// (a default one is capped). For setups changed in code (the Python module's `set`).
void check_cross_keys(const SimulationSetup& setup, const std::string& name);

/// Writes the effective configuration of a run: the scene file with absolute file paths, the
/// seed and the overrides applied, and the derived values (gain, absorption, EPSG...) under
/// `derived`, so that simulating it again reproduces the run exactly. `product_flags` (the
/// `simulate` options of the products, product_option_flags()) are not scene settings: the
/// header lists them, to be given again. `absolute_files` false: the scene's relative file paths
/// are kept as they are (a dataset item, whose files hold within the dataset directory).
void write_effective_config(const std::string& scene_path, const SimulationOverrides& overrides,
                            const SimulationSetup& setup, const Simulator& sim,
                            const std::filesystem::path& out_path,
                            const std::vector<std::string>& product_flags = {},
                            bool absolute_files = true);

/// Parses "YYYY-MM-DDTHH:MM:SS[.ffffff]Z" (UTC); throws InputError naming `what`.
UtcTime parse_utc(const std::string& text, const std::string& what);
std::string format_utc(UtcTime t);

}  // namespace sonarsynth
