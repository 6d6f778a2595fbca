// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/run_simulation.hpp"

#include <time.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "sonarsynth/formats/config/label_sets.hpp"
#include "sonarsynth/formats/products/product_metadata.hpp"
#include "sonarsynth/formats/products/sink_threads.hpp"
#include "sonarsynth/formats/registry/output_dir.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"

namespace sonarsynth {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double process_cpu_s() {
  timespec ts{};
  if (::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The waterfalls that have label rasters (a line without pings has none).
std::vector<labels::LabelImage> waterfall_label_images(const std::filesystem::path& dir,
                                                       const SurveyProductOptions& po,
                                                       const std::vector<std::string>& lines) {
  std::vector<labels::LabelImage> out;
  if (!po.waterfalls || !po.truth) return out;
  for (const std::string& name : lines) {
    labels::LabelImage li{name + "_waterfall.png",
                          name + "_truth_class.tif",
                          name + "_truth_instance.tif",
                          name + "_waterfall",
                          name,
                          ""};
    if (std::filesystem::exists(dir / li.image) && std::filesystem::exists(dir / li.classes)) {
      out.push_back(li);
    }
  }
  return out;
}

std::vector<labels::LabelImage> mosaic_label_images(const std::filesystem::path& dir,
                                                    const SurveyProductOptions& po) {
  labels::LabelImage li{
      "mosaic_rgb.tif", "truth_mosaic_class.tif", "truth_mosaic_instance.tif", "mosaic", "",
      "mosaic.tif"};
  if (!po.mosaic || !po.truth || !std::filesystem::exists(dir / li.classes)) return {};
  return {li};
}

// The slant ranges the seabed below the sensor fills with its echo: the pulse's extent (c tau / 2,
// a chirp's compressed c / 2B) plus one sample (the sample the nadir range falls in).
double first_return_extent_m(const SonarConfig& s) {
  return s.pulse_window_m() + s.sample_spacing_m();
}

// The products' options of a run: those asked for, with what the simulation file sets (truth,
// display window, output.mosaic).
SurveyProductOptions product_options(const SimulationSetup& setup,
                                     const SurveyProductOptions& asked) {
  SurveyProductOptions po = asked;
  po.truth = po.truth && setup.config.truth;
  po.truth_grazing = setup.truth_grazing;
  if (setup.display_linear) po.display_linear_full_scale = setup.config.output.max_value;
  if (setup.display_window_db) {
    // 10 log10(sample / full scale) to the display's 10 log10(sample) (docs/labels.md).
    const double full_scale_db = 10.0 * std::log10(setup.config.output.max_value);
    po.display_window_db =
        std::pair<double, double>{setup.display_window_db->first + full_scale_db,
                                  setup.display_window_db->second + full_scale_db};
  }
  // output.mosaic: nadir blanking and gain normalisation (docs/scene-format.md).
  const MosaicProcessing& mp = setup.mosaic_processing;
  po.mosaic_options.nadir_fill = mp.nadir != MosaicProcessing::Nadir::blank;
  po.mosaic_options.nadir_blank_m =
      mp.nadir == MosaicProcessing::Nadir::raw ? 0.0 : first_return_extent_m(setup.config.sonar);
  po.gain_normalisation = mp.gain;
  return po;
}

// One writer per format of output.formats into `dir`, each to run on a thread of its own
// (appended to `threaded`); their compatibility warnings into `result`.
std::vector<std::unique_ptr<SurveyFileSink>> sonar_file_writers(
    const SimulationSetup& setup, const Simulator& sim, const std::filesystem::path& dir,
    RunResult& result, std::vector<detail::ParallelSink::Threaded>& threaded) {
  SurveyWriterContext files_context;
  files_context.dir = dir;
  files_context.line_names = result.line_names;
  files_context.frame = &setup.scene.frame;
  files_context.sonar = &setup.config.sonar;
  files_context.simulator = &sim;
  files_context.scene_name = setup.scene.name;
  files_context.sample_format = setup.sample_format;
  files_context.allow_more_than_8192_samples = setup.allow_more_than_8192_samples;
  files_context.bag_truth = setup.bag_truth;
  std::vector<std::unique_ptr<SurveyFileSink>> sonar_files;
  for (const SonarFormat* f : sonar_formats()) {
    if (!setup.writes_format(f->name)) continue;
    sonar_files.push_back(f->create_survey_writer(files_context));
    for (const auto& w : sonar_files.back()->compatibility_warnings()) {
      result.compatibility_warnings.push_back(w);
    }
    threaded.push_back({sonar_files.back().get(), std::string(f->name)});
  }
  return sonar_files;
}

// What the label sets need of the run: its geometry, the lines' tracks and the display window.
labels::LabelContext label_context(const SimulationSetup& setup, const SurveyProductOptions& po,
                                   const std::vector<std::string>& line_names,
                                   const std::vector<labels::LineTrack>* tracks,
                                   const std::filesystem::path& final_dir) {
  labels::LabelContext context;
  context.frame = &setup.scene.frame;
  context.sample_spacing_m = setup.config.sonar.sample_spacing_m();
  context.side_cols = setup.config.sonar.samples_per_channel;
  context.line_names = line_names;
  context.tracks = tracks;
  context.final_dir = std::filesystem::absolute(final_dir);
  if (po.display_linear_full_scale > 0.0) {
    context.display_fixed = true;
    context.display = {0.0, 1.0, po.display_linear_full_scale};
  } else if (po.display_window_db) {
    context.display_fixed = true;
    context.display = {po.display_window_db->first, po.display_window_db->second, 0.0};
  }
  return context;
}

}  // namespace

RunResult run_simulation(const std::string& scene_path, const std::filesystem::path& out_dir,
                         const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_s();
  RunResult result;
  const auto warn = [&](const std::string& w) {
    result.warnings.push_back(w);
    if (options.on_warning) options.on_warning(w);
  };

  // The setup owns the scene; the Simulator and the products share it (aliasing pointer).
  const auto setup =
      std::make_shared<SimulationSetup>(load_simulation(scene_path, options.overrides));
  const std::shared_ptr<const Scene> scene(setup, &setup->scene);
  SurveyProductOptions po = product_options(*setup, options.products);

  // Check the whole run before anything is created (formats/config/run_check.cpp).
  result.plan = check_simulation(scene_path, *setup,
                                 {po.mosaic, po.waterfalls, po.truth, po.mosaic_pixel_m}, out_dir);
  for (const auto& w : result.plan.warnings) warn(w);
  OutputDirectory out(out_dir, options.overwrite, {scene_path});

  const Survey survey = setup->make_survey();
  const Simulator sim(scene, setup->config, setup->reference_altitude_m,
                      pilot_poses(survey, scene->bathymetry));

  for (const SurveyLine& l : setup->lines) result.line_names.push_back(l.name);
  // The sonar files: one writer per format of output.formats, in the order of the format list
  // (formats/registry/sonar_formats.cpp).
  std::vector<detail::ParallelSink::Threaded> threaded;
  const std::vector<std::unique_ptr<SurveyFileSink>> sonar_files =
      sonar_file_writers(*setup, sim, out.file(""), result, threaded);

  po.write_options.overwrite = true;  // inside our own fresh temporary directory
  po.write_options.metadata = run_metadata(scene->name, setup->config, sim.gain_db());
  po.write_options.quantity = setup->config.output.quantity == SampleQuantity::amplitude
                                  ? "backscatter (linear amplitude: the stored envelope)"
                                  : "backscatter (linear intensity)";
  // One thread asked for (`--threads 1`, a Dask worker's item) means one core: the files and
  // products are then written on the rendering thread, in the same order (the same bytes).
  const bool one_core = setup->config.threads == 1;
  if (one_core) po.background_images = false;
  // The bathymetry grid (31 MB on the paper scene) is read by the renderer and by the mosaic's
  // gridding only: when the mosaic has gridded the last ping every ping has been rendered, and
  // the grid is freed before the mosaic files are written (nothing below reads it).
  po.after_last_bathymetry_use = [&setup] { setup->scene.bathymetry.release_heights(); };
  // The waterfalls' boxes and chips made as their rows are written (docs/labels.md).
  std::optional<labels::LabelPass> label_pass;
  if (setup->labels.any() && po.truth && po.waterfalls) {
    labels::LabelPass& lp = label_pass.emplace(out.file(""), setup->labels);
    po.waterfall_rows = [&lp](const std::string& line) { return lp.image_tap(line); };
    po.label_rows = [&lp](const std::string& line) { return lp.label_tap(line); };
  }
  SurveyProducts products(out.file(""), scene, setup->config.sonar, setup->lines, po);
  RunStatistics stats;
  // The sonar files and each product on a thread of their own, fed through bounded queues
  // while the survey renders; each consumes the pings in survey order, so the files do not
  // depend on the thread count or the schedule. The statistics are cheap: on the rendering side.
  for (const auto& [name, part] : products.parts()) threaded.push_back({part, name});
  std::vector<PingSink*> inline_sinks = {&stats};
  // The lines' tracks and truth ground positions for the chip records (docs/labels.md).
  std::optional<labels::TrackRecorder> track;
  if (setup->labels.chips && po.truth && po.waterfalls) {
    const std::size_t side = setup->config.sonar.samples_per_channel;
    inline_sinks.push_back(
        &track.emplace(setup->lines.size(), side, labels::chip_columns(2 * side, setup->labels)));
  }
  if (one_core) {
    for (const auto& t : threaded) inline_sinks.push_back(t.sink);
    threaded.clear();
  }
  detail::ParallelSink sink(inline_sinks, threaded);

  const auto t_render = std::chrono::steady_clock::now();
  result.timings = sim.run(survey, sink, options.progress);
  result.run_s = seconds_since(t_render);
  result.products_s = products.finish_s();
  result.output_cpu_s = sink.thread_cpu_s();
  for (const auto& w : products.writer_cpu_s()) result.output_cpu_s.push_back(w);
  // Boxes and chips from the label rasters just written (output.labels, docs/labels.md).
  labels::LabelSetResult label_sets;
  if (setup->labels.any() && po.truth) {
    const auto t_labels = std::chrono::steady_clock::now();
    const labels::LabelContext context = label_context(
        *setup, po, result.line_names, track ? &track->tracks() : nullptr, out.final_dir());
    label_sets = labels::write_label_sets(
        out.file(""), waterfall_label_images(out.file(""), po, result.line_names),
        mosaic_label_images(out.file(""), po), setup->labels, context,
        label_pass ? &*label_pass : nullptr);
    result.labels_s = seconds_since(t_labels);
  }
  write_effective_config(scene_path, options.overrides, *setup, sim, out.file("effective.yaml"),
                         product_option_flags(options.products), !options.relative_files);
  out.commit();

  const bool per_ping = setup->config.output.normalise == OutputScaling::Normalise::per_ping_max;
  for (const auto& w : stats.warnings(result.line_names, setup->config.output.max_value,
                                      per_ping ? std::nan("") : sim.gain_db())) {
    warn(w);
  }
  for (const auto& sonar_file : sonar_files) {
    for (const auto& f : sonar_file->files())
      result.files.push_back(out.final_dir() / f.filename());
  }
  for (const auto& f : products.files()) result.files.push_back(out.final_dir() / f.filename());
  for (const auto& f : label_sets.files) result.files.push_back(out.final_dir() / f);
  result.files.push_back(out.final_dir() / "effective.yaml");
  result.notes = products.notes();
  result.notes.insert(result.notes.end(), label_sets.notes.begin(), label_sets.notes.end());
  result.line_statistics = stats.lines();
  result.total_pings = survey.total_pings();
  result.along_track = sim.along_track();
  result.along_track_tolerance_db = setup->config.quality.along_track_tolerance_db;
  result.gain_db = sim.gain_db();
  result.total_s = seconds_since(t0);
  result.cpu_s = process_cpu_s() - cpu0;
  return result;
}

}  // namespace sonarsynth
