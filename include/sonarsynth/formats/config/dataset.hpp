// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/simulation_file.hpp"

namespace sonarsynth {

/// A number drawn uniformly from [lo, hi]; lo == hi is a fixed value. In a spec file: a number,
/// or a list [lo, hi].
struct NumberRange {
  double lo = 0.0;
  double hi = 0.0;
};

/// A name drawn with the given weights. In a spec file: a name, a list of names (equal weights)
/// or a map {name: weight}.
struct WeightedChoice {
  std::vector<std::string> names;
  std::vector<double> weights;  ///< > 0, same length as names
};

/// The distributions of one object type (`objects.types.<type>` in a spec file).
struct DatasetObjectType {
  std::string type;  ///< rock, box, pipe, moored or mesh
  double weight = 1.0;
  NumberRange diameter_m{1.0, 1.0};  ///< rock, pipe, moored
  NumberRange length_m{2.0, 2.0};    ///< box, pipe
  NumberRange width_m{1.0, 1.0};     ///< box
  NumberRange height_m{1.0, 1.0};    ///< box; moored: height of the centre above the seabed
  // mesh
  /// The models as the spec names them (a path relative to the spec file, or the name of a
  /// shipped model: `mine`, `wreck`), with their weights.
  WeightedChoice models;
  std::vector<std::string> model_files;  ///< absolute path of each of models.names
  /// The copy of each of models.names in the dataset directory, relative to it
  /// ("models/wreck.obj"; prepare_dataset_dir writes it): the item scenes name it relatively.
  std::vector<std::string> model_copies;
  NumberRange scale{1.0, 1.0};  ///< uniform scale of the model, > 0
  /// Largest horizontal distance of a vertex from its model's origin over the models, at scale
  /// 1, metres (read from the files at load: the grid's margin).
  double model_radius_m = 0.0;
};

/// A dataset specification (docs/dataset.md): N scenes drawn from distributions. Every item is
/// a pure function of (spec, seed, index): see dataset_item_seed() and dataset_item_scene().
struct DatasetSpec {
  std::string file;  ///< the spec file, for messages
  std::string text;  ///< the spec file's text (copied into the dataset directory)
  std::string name = "dataset";
  std::uint64_t seed = 0;
  std::size_t count = 1;
  // location and seabed
  double lat_deg = 43.0;
  double lon_deg = 5.0;
  double cell_m = 0.25;
  NumberRange depth_m{20.0, 20.0};
  WeightedChoice material{{"sand"}, {1.0}};
  NumberRange slope_deg{0.0, 0.0};
  NumberRange roughness_rms_m{0.05, 0.05};
  NumberRange roughness_wavelength_m{20.0, 20.0};
  double ripples_probability = 0.0;
  NumberRange ripple_wavelength_m{1.5, 1.5};
  NumberRange ripple_amplitude_m{0.03, 0.03};
  // objects
  NumberRange object_count{0.0, 0.0};  ///< integers, inclusive
  std::vector<DatasetObjectType> object_types;
  NumberRange burial{0.0, 0.0};  ///< embed: fraction of the height below the seabed, [0, 0.99)
  NumberRange object_heading_deg{0.0, 360.0};
  NumberRange across_track_m{5.0, 25.0};  ///< |offset| of an object from the track
  // survey
  double line_length_m = 100.0;
  NumberRange line_heading_deg{0.0, 360.0};
  NumberRange altitude_m{8.0, 8.0};
  NumberRange speed_m_s{2.0, 2.0};
  // sonar and noise
  WeightedChoice sonar_preset{{"seascan-hds-600"}, {1.0}};
  std::optional<NumberRange> range_m;  ///< replaces the preset's range when given
  std::optional<std::size_t> samples;  ///< replaces the preset's samples when given
  WeightedChoice noise_model{{"speckle"}, {1.0}};
  NumberRange snr_db{20.0, 20.0};
  /// The optional knobs of domain randomisation (docs/dataset.md, "Domain randomisation"), by
  /// spec key ("survey.disturbance.roll_deg", "sonar.frequency_khz", ...), in the key's units. A
  /// knob left out writes nothing into the scene: the scene file's default holds.
  std::map<std::string, NumberRange> knobs;
  // run
  std::string quality = "fast";  ///< QualityConfig preset: fast, default, high
  bool mosaic = false;
  bool waterfalls = true;
  bool truth = true;
  /// run.products.labels: the same block as output.labels in a scene file (docs/labels.md),
  /// written into every item's scene file as it was given ("" = no labels).
  std::string labels_yaml;
  LabelOutput labels;  ///< run.products.labels as read
  /// run.display_window_db: the display window of every waterfall, mosaic_rgb and chip of the
  /// dataset, 10 log10(sample / full scale) (output.display_window_db of the item scenes,
  /// docs/labels.md), so that a grey level means the same in every item. The default is about
  /// the 1st-99th percentile window of the waterfall of an item (docs/dataset.md).
  std::array<double, 2> display_window_db{-28.0, 0.0};
  /// run.split: the fractions of the items in train, val and test (each >= 0, sum 1); all
  /// images and chips of an item belong to the item's split. Not given: no split.
  bool split = false;
  double split_train = 1.0, split_val = 0.0, split_test = 0.0;
  /// The spec without `count` (canonical YAML): two specs with the same identity draw the same
  /// items, so a dataset directory may be grown or shrunk by changing `count` alone.
  std::string identity;
};

/// The largest spec file read (bytes).
inline constexpr std::size_t kMaxDatasetSpecBytes = std::size_t{1} << 20;

/// Reads and validates a spec file; throws InputError / FormatError naming the file, the field
/// and the value.
DatasetSpec load_dataset_spec(const std::string& path);
/// As load_dataset_spec(), from YAML text: `name` stands for the file in messages.
DatasetSpec load_dataset_spec_from_string(const std::string& yaml_text, const std::string& name);

/// The seed of item `index`: a keyed hash of the index with the spec's seed as key, so that
/// every item is independent of the others and of the order in which they run.
std::uint64_t dataset_item_seed(const DatasetSpec& spec, std::size_t index);

/// One drawn scene: the scene file text (docs/scene-format.md) and what it holds.
struct DatasetItemScene {
  std::size_t index = 0;
  std::uint64_t seed = 0;
  std::string yaml;  ///< the scene; mesh models by absolute path (it loads from anywhere)
  /// The scene as run_dataset_item writes it (items/NNNNNN/scene.yaml): the same, with each mesh
  /// model named by its copy in the dataset directory, relative to the item's directory.
  std::string dataset_yaml;
  std::map<std::string, int> object_counts;  ///< by type
  /// The values drawn for this item by spec key ("survey.altitude_m", "sonar.preset", ...), so
  /// that results can be sliced by them: numbers in the units of the key, names as text; the
  /// values of object k under "objects[k].<key>". Each is the value the scene text holds (as
  /// rounded there); docs/dataset.md lists the keys.
  std::map<std::string, double> drawn_numbers;
  std::map<std::string, std::string> drawn_names;
};
/// Draws item `index` (< spec.count); a pure function of (spec, index).
DatasetItemScene dataset_item_scene(const DatasetSpec& spec, std::size_t index);

/// The split of item `index` ("train", "val" or "test"; "" without run.split). Interleaved by
/// index so that among the first n items, for every n, each split holds its fraction of n to
/// within one item: a dataset grown by raising `count` keeps the split of every item it had.
std::string dataset_item_split(const DatasetSpec& spec, std::size_t index);

/// What became of one item.
struct DatasetItemResult {
  std::size_t index = 0;
  std::uint64_t seed = 0;
  std::string status;              ///< "done" (rendered now), "skipped" (already done), "failed"
  std::string error;               ///< when failed
  std::vector<std::string> files;  ///< relative to the dataset directory
  std::map<std::string, int> object_counts;
  std::map<std::string, double> drawn_numbers;     ///< DatasetItemScene::drawn_numbers
  std::map<std::string, std::string> drawn_names;  ///< DatasetItemScene::drawn_names
  std::uint64_t pings = 0;
  std::string split;  ///< dataset_item_split()
  /// Each file of the item (paths relative to the item directory; item.json itself excepted)
  /// with its size and SHA-256, as written: a resumed run checks the sizes (and with `verify`
  /// the hashes) before it counts the item as done.
  struct FileRecord {
    std::string path;
    std::uint64_t bytes = 0;
    std::string sha256;
  };
  std::vector<FileRecord> file_records;
  /// A done item found damaged (a file missing or changed) and rendered again: what was wrong.
  std::string repaired;
  double seconds = 0.0;  ///< wall time of this call
};

/// `items/000042`: the directory of item `index`, relative to the dataset directory.
std::string dataset_item_dir(std::size_t index);

/// Creates the dataset directory if needed and records the spec in it (`spec.yaml`); throws
/// InputError if the directory holds a dataset made from another spec.
void prepare_dataset_dir(const DatasetSpec& spec, const std::filesystem::path& dir);

/// Renders item `index` into `dir` (prepare_dataset_dir first): the scene, the run_simulation
/// products and `item.json` are written into a temporary directory that is renamed into place
/// when complete; an item already in place is skipped. `threads` 0 = all cores (the files do not
/// depend on it). Throws InputError / FormatError naming the index and seed when the item fails
/// (and records the failure in `failed/<index>.json`). An item already in place whose files do
/// not match its record (a file missing or resized; with `verify` also a SHA-256 changed) is
/// rendered again, and DatasetItemResult::repaired says what was wrong.
DatasetItemResult run_dataset_item(const DatasetSpec& spec, const std::filesystem::path& dir,
                                   std::size_t index, unsigned threads = 0, bool verify = false);

/// Records item `index` (< spec.count) as failed with `error` in `dir/failed/<index>.json`,
/// atomically: {index, seed, seed_text, status: failed, error}, the record run_dataset_item()
/// writes for a failed item and write_dataset_manifest() reads (docs/dataset.md). For a runner
/// other than run_dataset() (sonarsynth_dask) whose item failed outside run_dataset_item(): a
/// worker lost, an exception of its own. Creates `dir/failed` if needed; throws InputError for
/// an index beyond count, FormatError if the record cannot be written.
void record_dataset_failure(const DatasetSpec& spec, const std::filesystem::path& dir,
                            std::size_t index, const std::string& error);

/// Options of run_dataset().
struct DatasetRunOptions {
  unsigned threads = 0;         ///< per item; 0 = all cores
  std::size_t shard_index = 0;  ///< this run does the items i with i % shard_count == shard_index
  std::size_t shard_count = 1;  ///< >= 1
  /// Only the items in [first_item, end_item) (of this shard); end_item is capped at count.
  std::size_t first_item = 0;
  std::size_t end_item = static_cast<std::size_t>(-1);
  bool verify = false;  ///< check the SHA-256 of every file of the items already done
  /// Called after each item (done, skipped or failed): (items finished, items of this shard).
  std::function<void(std::size_t, std::size_t, const DatasetItemResult&)> progress;
};

/// What run_dataset() did.
struct DatasetRunResult {
  std::vector<DatasetItemResult> items;  ///< this shard's, in index order
  std::size_t done = 0, skipped = 0, failed = 0;
  std::size_t repaired = 0;  ///< of `done`: items found damaged and rendered again
  double seconds = 0.0;
};

/// Parses "K/N" (0 <= K < N) for --shard; throws InputError naming `what`.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text, const std::string& what);

/// Parses "A:B" (0 <= A < B, either may be left out: ":B", "A:") for --items into [A, B); throws
/// InputError naming `what`.
std::pair<std::size_t, std::size_t> parse_item_range(const std::string& text,
                                                     const std::string& what);

/// Runs this shard's items one after the other (a failed item is recorded and the run goes on),
/// then writes the manifest (write_dataset_manifest).

DatasetRunResult run_dataset(const DatasetSpec& spec, const std::filesystem::path& dir,
                             const DatasetRunOptions& options = {});

/// Writes `manifest.jsonl` (one JSON object per item in index order: index, seed, seed_text,
/// status done / failed / pending, split, dir, files, objects, drawn, pings, error) and
/// `summary.json` from the items' records in `dir`, and with run.products.labels the
/// dataset-level annotation files merged over the done items (docs/dataset.md), each file
/// atomically. Any process may call it at any time.
void write_dataset_manifest(const DatasetSpec& spec, const std::filesystem::path& dir);

}  // namespace sonarsynth
