// SPDX-License-Identifier: MIT
// `sonarsynth simulate SCENE.yaml -o OUTDIR`: renders the survey of a scene file and writes one
// XTF file per survey line, the effective configuration and (when enabled) mosaic, waterfalls
// and truth products.
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/output_dir.hpp"
#include "sonarsynth/formats/product_metadata.hpp"
#include "sonarsynth/formats/run_check.hpp"
#include "sonarsynth/formats/simulation_file.hpp"
#include "sonarsynth/formats/survey_products.hpp"
#include "sonarsynth/formats/survey_writer.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth simulate SCENE.yaml -o OUTDIR [options]\n\n"
    "Renders the survey described in SCENE.yaml (format: docs/scene-format.md) and writes into\n"
    "OUTDIR: one XTF file per survey line (<line>.xtf), a waterfall image per line\n"
    "(<line>_waterfall.png), per-sample truth per line (<line>_truth.tif: class, object id,\n"
    "grazing angle), the survey mosaic (mosaic.tif, float32 linear intensity, COG by default),\n"
    "its display copy (mosaic_rgb.tif), the truth mosaic (truth_mosaic.tif: object ids on the\n"
    "same grid) and effective.yaml, the configuration that reproduces the run exactly.\n"
    "OUTDIR appears only when everything in it is complete.";

}  // namespace

int run_simulate(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string scene_path, out_dir, quality;
  bool overwrite = false, quiet = false;
  std::string seed;
  double range_m = 0;
  std::size_t samples = 0;
  long long threads = 0;
  double res_m = 0.25;
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
    ("seed", po::value(&seed), "random seed (overrides the scene file's)")
    ("range", po::value(&range_m), "maximum slant range, metres (overrides sonar.range_m)")
    ("samples", po::value(&samples), "samples per channel (overrides sonar.samples)")
    ("quality", po::value(&quality), "renderer quality: fast, default or high")
    ("threads", po::value(&threads), "worker threads (default: all cores); output is identical for any value")
    ("res", po::value(&res_m)->default_value(0.25), "mosaic pixel size, metres")
    ("of", po::value(&of)->default_value("COG"), "mosaic format: COG or GTiff")
    ("co", po::value(&co)->composing(), "mosaic creation option KEY=VALUE (repeatable)")
    ("no-mosaic", po::bool_switch(&no_mosaic), "skip the mosaics")
    ("no-waterfall", po::bool_switch(&no_waterfall), "skip the waterfall images")
    ("waterfall-max-pixels", po::value(&waterfall_max_pixels),
     "largest waterfall image; longer lines are decimated along track (default 2^28)")
    ("no-truth", po::bool_switch(&no_truth), "skip the truth products");
  // clang-format on
  po::positional_options_description pos;
  pos.add("scene", 1);
  po::variables_map vm;
  if (!parse(args, opts, pos, vm, kUsage)) return 0;

  SimulationOverrides ov;
  if (vm.count("seed")) ov.seed = parse_uint64(seed, "seed");
  if (vm.count("range")) ov.range_m = range_m;
  if (vm.count("samples")) ov.samples = samples;
  if (vm.count("quality")) ov.quality = quality;
  if (vm.count("threads")) ov.threads = checked_thread_count(threads, 1);
  // Options of the products, recorded in effective.yaml (they are not scene settings).
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    for (const std::string f : {"--res", "--of", "--co", "--waterfall-max-pixels"}) {
      if (a.rfind(f + "=", 0) == 0) ov.product_flags.push_back(a);
      if (a == f && i + 1 < args.size()) ov.product_flags.push_back(a + " " + args[i + 1]);
    }
    for (const std::string f : {"--no-mosaic", "--no-waterfall", "--no-truth"}) {
      if (a == f) ov.product_flags.push_back(a);
    }
  }

  const double t0 = now_s();
  SimulationSetup setup = load_simulation(scene_path, ov);
  // Check the whole run before anything is created (formats/run_check.cpp).
  const RunPlan plan = check_simulation(
      scene_path, setup, {!no_mosaic, !no_waterfall, !no_truth && setup.config.truth, res_m},
      out_dir);
  for (const auto& w : plan.warnings) std::cerr << "warning: " << w << "\n";
  OutputDirectory out(out_dir, overwrite, {scene_path});

  const Survey survey = setup.make_survey();
  Simulator sim(setup.scene, setup.config, setup.reference_altitude_m,
                pilot_poses(survey, setup.scene.bathymetry));

  xtf::WriterOptions xo;
  xo.overwrite = true;  // inside our own fresh temporary directory
  xo.sample_encoding = setup.sample_format == "u8"    ? xtf::SampleEncoding::kUint8
                       : setup.sample_format == "f32" ? xtf::SampleEncoding::kFloat32
                                                      : xtf::SampleEncoding::kUint16;
  xo.allow_more_than_8192_samples = setup.allow_more_than_8192_samples;
  xo.frequency_khz = setup.config.sonar.frequency_hz / 1e3;
  xo.horizontal_beam_angle_rad = setup.config.sonar.horizontal_beam_width_rad;
  xo.tilt_angle_rad = setup.config.sonar.tilt_rad;
  xo.note = "sonarsynth synthetic survey of scene '" + setup.scene.name + "', seed " +
            std::to_string(setup.config.seed) + ", gain " + std::to_string(sim.gain_db()) +
            " dB after TVG 30logR+2aR";
  if (!quiet) {
    for (const auto& w : xo.compatibility_warnings()) std::cerr << "warning: " << w << "\n";
  }
  std::vector<std::string> names;
  for (std::size_t i = 0; i < setup.lines.size(); ++i) names.push_back(setup.lines[i].name);
  XtfSurveyWriter xtf_out(out.file(""), names, setup.scene.frame, setup.config.sonar, xo);

  SurveyProductOptions po_opts;
  po_opts.mosaic = !no_mosaic;
  po_opts.waterfalls = !no_waterfall;
  po_opts.truth = !no_truth && setup.config.truth;
  po_opts.mosaic_pixel_m = res_m;
  po_opts.waterfall_max_pixels = waterfall_max_pixels;
  if (of == "COG" || of == "cog") {
    po_opts.write_options.format = MosaicRasterFormat::cog;
  } else if (of == "GTiff" || of == "gtiff") {
    po_opts.write_options.format = MosaicRasterFormat::gtiff;
  } else {
    throw InputError("--of = '" + of + "'. Violated constraint: COG or GTiff");
  }
  po_opts.write_options.creation_options = parse_key_values(co, "co");
  po_opts.write_options.overwrite = true;  // inside our own fresh temporary directory
  po_opts.write_options.metadata = run_metadata(setup.scene.name, setup.config, sim.gain_db());
  SurveyProducts products(out.file(""), setup.scene, setup.config.sonar, setup.lines, po_opts);
  RunStatistics stats(setup.lines.size());
  TeeSink sink({&xtf_out, &products, &stats});

  ProgressBar bar(quiet, "pings");
  const double t_render = now_s();
  const RenderTimings timings = sim.run(
      survey, sink, [&](std::uint64_t done, std::uint64_t total) { bar.update(done, total); });
  bar.finish();
  const double render_s = now_s() - t_render;
  const double t_mosaic = now_s();
  products.finish();
  const double mosaic_s = now_s() - t_mosaic;
  write_effective_config(scene_path, ov, setup, sim, out.file("effective.yaml"));
  out.commit();
  for (const auto& w : stats.warnings(names, setup.config.output.max_value, sim.gain_db()))
    std::cerr << "warning: " << w << "\n";

  if (!quiet) {
    const double n = static_cast<double>(survey.total_pings());
    std::cout << "sonarsynth simulate: " << survey.total_pings() << " pings on "
              << setup.lines.size() << " line(s) in " << std::fixed << std::setprecision(2)
              << render_s << " s (" << std::setprecision(0) << n / render_s << " pings/s), total "
              << std::setprecision(2) << now_s() - t0 << " s\n"
              << "  per ping (CPU): profile " << std::setprecision(1) << 1e6 * timings.profile_s / n
              << " us, render " << 1e6 * timings.render_s / n << " us, noise+scaling "
              << 1e6 * timings.noise_s / n << " us\n";
    const AlongTrackChoice& at = sim.along_track();
    std::cout << "  along-track planes: " << at.planes;
    if (at.automatic) {
      std::cout << " (auto from " << at.pilot_pings << " pilot pings: estimated error "
                << std::setprecision(2) << at.estimated_error_db << " dB, tolerance "
                << setup.config.quality.along_track_tolerance_db << " dB, " << std::setprecision(0)
                << 1e3 * at.pilot_s << " ms)";
    }
    std::cout << "\n  estimated before the run: " << plan.total_pings << " pings, "
              << std::setprecision(3) << static_cast<double>(plan.output_bytes) / 1e9
              << " GB written at most, " << static_cast<double>(plan.memory_bytes) / 1e9
              << " GB of memory";
    std::cout << "\n  mosaic written in " << std::setprecision(2) << mosaic_s << " s\n";
    for (const auto& f : xtf_out.files()) {
      std::cout << "  " << (out.final_dir() / f.filename()).string() << "\n";
    }
    for (const auto& f : products.files()) {
      std::cout << "  " << (out.final_dir() / f.filename()).string() << "\n";
    }
    std::cout << "  " << (out.final_dir() / "effective.yaml").string() << "\n";
    for (const auto& note : products.notes()) std::cout << "  note: " << note << "\n";
    for (std::size_t i = 0; i < setup.lines.size(); ++i) {
      const RunStatistics::Line& l = stats.lines()[i];
      const double samples_n = static_cast<double>(std::max<std::uint64_t>(l.samples, 1));
      std::cout << "  line " << names[i] << ": " << l.pings << " pings, saturated "
                << std::setprecision(3) << 100.0 * static_cast<double>(l.saturated) / samples_n
                << " %, non-finite " << 100.0 * static_cast<double>(l.invalid) / samples_n
                << " %, no seabed " << l.no_seabed_pings << " pings\n";
    }
  }
  return 0;
}

}  // namespace sonarsynth::cli
