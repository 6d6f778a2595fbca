// SPDX-License-Identifier: MIT
// `sonarsynth simulate SCENE.yaml -o OUTDIR`: renders the survey of a scene file and writes one
// XTF file per survey line, the effective configuration and (when enabled) mosaic, waterfalls
// and truth products.
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth simulate SCENE.yaml -o OUTDIR [options]\n\n"
    "Renders the survey described in SCENE.yaml (format: docs/scene-format.md) and writes into\n"
    "OUTDIR: one XTF file per survey line (<line>.xtf), a waterfall image per line\n"
    "(<line>_waterfall.png), per-sample truth per line (<line>_truth.tif: class, object id,\n"
    "grazing angle), the survey mosaic (mosaic.tif, float32, the samples gridded linearly, COG by "
    "default),\n"
    "its display copy (mosaic_rgb.tif), the truth mosaic (truth_mosaic.tif: object ids on the\n"
    "same grid) and effective.yaml, the configuration that reproduces the run exactly.\n"
    "OUTDIR appears only when everything in it is complete.";

void print_summary(const RunResult& r) {
  const double n = static_cast<double>(r.total_pings);
  std::cout << "sonarsynth simulate: " << r.total_pings << " pings on " << r.line_names.size()
            << " line(s) rendered and written in " << std::fixed << std::setprecision(2) << r.run_s
            << " s (" << std::setprecision(0) << n / r.run_s << " pings/s end to end), total "
            << std::setprecision(2) << r.total_s << " s, CPU " << r.cpu_s << " s\n"
            << "  per ping, thread time summed over the rendering threads (waits included): "
               "profile "
            << std::setprecision(1) << 1e6 * r.timings.profile_s / n << " us, render "
            << 1e6 * r.timings.render_s / n << " us, noise+scaling " << 1e6 * r.timings.noise_s / n
            << " us\n";
  if (!r.output_cpu_s.empty()) {
    std::cout << "  output threads, CPU:";
    const char* sep = " ";
    for (const auto& [name, s] : r.output_cpu_s) {
      std::cout << sep << name << " " << std::setprecision(2) << s << " s";
      sep = ", ";
    }
    std::cout << "\n";
  }
  const AlongTrackChoice& at = r.along_track;
  std::cout << "  along-track planes: " << at.planes;
  if (at.automatic) {
    std::cout << " (auto from " << at.pilot_pings << " pilot pings: estimated error "
              << std::setprecision(2) << at.estimated_error_db << " dB, tolerance "
              << r.along_track_tolerance_db << " dB, " << std::setprecision(0) << 1e3 * at.pilot_s
              << " ms)";
    if (at.object_planes > at.planes) {
      std::cout << "; " << at.object_planes << " over the range window of objects and shadows ("
                << std::setprecision(2) << at.object_estimated_error_db << " dB with objects, "
                << r.timings.window_sides << " ping sides, " << std::setprecision(0)
                << (r.timings.window_sides > 0 ? static_cast<double>(r.timings.window_samples) /
                                                     static_cast<double>(r.timings.window_sides)
                                               : 0.0)
                << " samples each on average)";
    }
  }
  if (r.timings.refined_sides > 0) {
    std::cout << "; " << r.timings.refined_sides << " ping sides near small objects with "
              << std::setprecision(1)
              << static_cast<double>(r.timings.refined_planes) /
                     static_cast<double>(r.timings.refined_sides)
              << " planes on average";
  }
  std::cout << "\n  estimated before the run: " << r.plan.total_pings << " pings, "
            << std::setprecision(3) << static_cast<double>(r.plan.output_bytes) / 1e9
            << " GB written at most, " << static_cast<double>(r.plan.memory_bytes) / 1e9
            << " GB of memory";
  std::cout << "\n  mosaic written in " << std::setprecision(2) << r.products_s << " s\n";
  // The chips (output.labels.chips, docs/labels.md) are counted, not listed one by one.
  std::size_t chip_files = 0;
  std::filesystem::path chips_dir;
  for (const auto& f : r.files) {
    if (f.parent_path().parent_path().filename() == "chips") {
      ++chip_files;
      chips_dir = f.parent_path().parent_path();
      continue;
    }
    std::cout << "  " << f.string() << "\n";
  }
  if (chip_files > 0) {
    std::cout << "  " << chips_dir.string() << "/ (" << chip_files << " files)\n";
  }
  if (r.labels_s > 0.0) {
    std::cout << "  labels (boxes, chips) written in " << std::setprecision(2) << r.labels_s
              << " s\n";
  }
  for (const auto& note : r.notes) std::cout << "  note: " << note << "\n";
  for (std::size_t i = 0; i < r.line_names.size(); ++i) {
    const RunStatistics::Line& l = r.line_statistics[i];
    const double samples_n = static_cast<double>(std::max<std::uint64_t>(l.samples, 1));
    std::cout << "  line " << r.line_names[i] << ": " << l.pings << " pings, saturated "
              << std::setprecision(3) << 100.0 * static_cast<double>(l.saturated) / samples_n
              << " %, non-finite " << 100.0 * static_cast<double>(l.invalid) / samples_n
              << " %, no seabed " << l.no_seabed_pings << " pings\n";
  }
}

}  // namespace

int run_simulate(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string scene_path, out_dir;
  bool overwrite = false, quiet = false;
  long long threads = 0;
  double res_m = kDefaultMosaicPixelM;
  std::string of = "COG";
  std::vector<std::string> co;
  bool no_mosaic = false, no_waterfall = false, no_truth = false;
  std::size_t waterfall_max_pixels = SurveyProductOptions{}.waterfall_max_pixels;
  // clang-format off
  opts.add_options()
    ("scene", po::value(&scene_path)->required(), "scene file (YAML)")
    ("output,o", po::value(&out_dir)->required(), "output directory (must not exist unless --overwrite)")
    ("overwrite", po::bool_switch(&overwrite), "replace an existing output directory")
    ("quiet,q", po::bool_switch(&quiet), "no progress bar or summary")
    ("threads", po::value(&threads), "worker threads (default: all cores); output is identical for any value")
    ("res", po::value(&res_m)->default_value(kDefaultMosaicPixelM), "mosaic pixel size, metres")
    ("of", po::value(&of)->default_value("COG"), "mosaic format: COG or GTiff")
    ("co", po::value(&co)->composing(), "mosaic creation option KEY=VALUE (repeatable)")
    ("no-mosaic", po::bool_switch(&no_mosaic), "skip the mosaics")
    ("no-waterfall", po::bool_switch(&no_waterfall), "skip the waterfall images")
    ("waterfall-max-pixels", po::value(&waterfall_max_pixels),
     "largest waterfall image; longer lines are decimated along track (default 2^28)")
    ("no-truth", po::bool_switch(&no_truth), "skip the truth products");
  // clang-format on
  // The overrides of scene-file options, as the option table declares them.
  const std::vector<OverrideFlag> override_list = override_flags();
  for (const OverrideFlag& f : override_list) {
    opts.add_options()(f.name.c_str(), po::value<std::string>(), f.help.c_str());
  }
  po::positional_options_description pos;
  pos.add("scene", 1);
  po::variables_map vm;
  if (!parse(args, opts, pos, vm, kUsage)) return 0;

  SimulationOverrides ov;
  for (const OverrideFlag& f : override_list) {
    if (vm.count(f.name)) set_override(ov, f.name, vm[f.name].as<std::string>());
  }
  if (vm.count("threads")) ov.threads = checked_thread_count(threads, 1);

  RunOptions run;
  run.overrides = ov;
  run.overwrite = overwrite;
  SurveyProductOptions& po_opts = run.products;
  po_opts.mosaic = !no_mosaic;
  po_opts.waterfalls = !no_waterfall;
  po_opts.truth = !no_truth;
  po_opts.mosaic_pixel_m = res_m;
  po_opts.waterfall_max_pixels = waterfall_max_pixels;
  po_opts.write_options.format = parse_mosaic_raster_format(of, "--of");
  po_opts.write_options.creation_options = parse_key_values(co, "co");
  ProgressBar bar(quiet, "pings");
  bool bar_done = false;  // ended at the last ping, before the statistics' warnings
  run.progress = [&](std::uint64_t done, std::uint64_t total) {
    bar.update(done, total);
    if (done == total && !bar_done) {
      bar.finish();
      bar_done = true;
    }
  };
  run.on_warning = [](const std::string& w) { std::cerr << "warning: " << w << "\n"; };

  const RunResult r = run_simulation(scene_path, out_dir, run);
  if (!quiet) {
    for (const auto& w : r.compatibility_warnings) std::cerr << "warning: " << w << "\n";
    print_summary(r);
  }
  return 0;
}

}  // namespace sonarsynth::cli
