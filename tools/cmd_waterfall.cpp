// SPDX-License-Identifier: MIT
// `sonarsynth waterfall`: port | starboard waterfall image of a sonar file of any listed format.
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/output_paths.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"

namespace sonarsynth::cli {

int run_waterfall(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string input, output, altitude_source = "auto";
  WaterfallOptions wo;
  // clang-format off
  opts.add_options()
    ("input", po::value(&input)->required(),
     ("sonar file: " + sonar_format_names() + " (positional; the format is read from the content)").c_str())
    ("output,o", po::value(&output)->required(), "output image (.png or .tif)")
    ("grey", "grey scale instead of the black-brown-yellow colormap")
    ("slant-correct", "resample to ground range on a flat bottom (altitude of each ping)")
    ("altitude-source", po::value(&altitude_source)->default_value("auto"),
     "with --slant-correct: auto | header | track; auto = the header's unless missing, <= 0 "
     "or disagreeing with the bottom tracked from the first return (docs/conversion.md)")
    ("lo-db", po::value(&wo.lo_db), "fixed scaling: dB shown black (with --hi-db)")
    ("hi-db", po::value(&wo.hi_db), "fixed scaling: dB shown at full colour (with --lo-db)")
    ("linear", po::value(&wo.linear_full_scale),
     "linear scaling: sample / VALUE (e.g. 32767, the full scale of sonarsynth's u16 samples: "
     "the founding paper's grey level)")
    ("max-pixels", po::value(&wo.max_pixels)->default_value(wo.max_pixels),
     "largest image (columns x rows); a longer line is decimated along track (mean of N pings per row)");
  // clang-format on
  add_overwrite_quiet_options(opts);
  po::variables_map vm;
  if (!parse(args, opts, one_input(), vm,
             "usage: sonarsynth waterfall FILE -o IMAGE.png [options]\n\n"
             "Draws one row per ping: port far -> near | starboard near -> far (nadir in the\n"
             "middle), 10 log10 of the samples between the 1st and 99th percentiles of the file\n"
             "(or --lo-db/--hi-db, or the samples linearly with --linear) through the\n"
             "black-brown-yellow colormap (or --grey). A .png is at most 1 000 000 pixels\n"
             "wide (libpng): a wider ping is refused when it is read; a .tif has no such limit.")) {
    return 0;
  }
  if (vm.count("lo-db") != vm.count("hi-db")) {
    throw InputError("--lo-db and --hi-db. Violated constraint: give both or neither");
  }
  wo.fixed_db = vm.count("lo-db") > 0;
  if (wo.fixed_db && vm.count("linear")) {
    throw InputError("--linear and --lo-db/--hi-db. Violated constraint: give one scaling");
  }
  if (vm.count("linear") && !(wo.linear_full_scale > 0.0)) {
    throw InputError("--linear = " + std::to_string(wo.linear_full_scale) +
                     ". Violated constraint: --linear > 0");
  }
  wo.colormap = vm.count("grey") ? Colormap::grey : Colormap::black_brown_yellow;
  wo.slant_correct = vm.count("slant-correct") > 0;
  wo.altitude_source = parse_altitude_source(altitude_source, "--altitude-source");
  wo.overwrite = vm.count("overwrite") > 0;
  wo.validate();
  refuse_output_over_input({output}, {input});
  const WaterfallResult r = write_xtf_waterfall(input, output, wo);
  warn_reader_anomalies("waterfall", r.reader_anomalies, r.reader_anomaly_messages);
  if (!vm.count("quiet")) {
    std::cout << "wrote " << output << ": " << r.cols << " x " << r.rows << " pixels";
    if (r.pings_per_row > 1) {
      std::cout << " (" << r.pings << " pings decimated along track: each row the mean of "
                << r.pings_per_row << " pings, to fit --max-pixels " << wo.max_pixels << ")";
    }
    if (wo.slant_correct) {
      std::cout << "; altitude of " << r.pings_tracked_altitude << " of " << r.pings
                << " pings tracked from the first return";
    }
    std::cout << "\n";
  }
  return 0;
}

}  // namespace sonarsynth::cli
