// SPDX-License-Identifier: MIT
// libFuzzer target: a scene file (YAML, docs/scene-format.md) given as text, loaded with its
// survey, sonar, render, noise and output sections. Whatever the text, the loader must end with
// a scene or a sonarsynth::Error (InputError / FormatError naming the key and the value); any
// other exception escapes and is reported as a crash, as are crashes, hangs and leaks.
//
// Relative file references resolve in a directory that does not exist. Generated bathymetry is
// capped below (the loader accepts up to 10^6 x 10^6 nodes, which is a memory limit, not a
// parsing question): a document asking for more nodes than kMaxGeneratedNodes is not loaded.
#include <cpl_error.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

namespace {

constexpr double kMaxGeneratedNodes = 1 << 18;

// Whether the document asks for a generated grid larger than the cap (false if it cannot tell:
// the loader then reports the problem itself).
bool too_large(const std::string& text) {
  try {
    const YAML::Node g = YAML::Load(text)["bathymetry"]["generate"];
    const YAML::Node size = g["size_m"];
    const YAML::Node cell = g["cell_m"];
    if (!cell.IsDefined() || !cell.IsScalar()) return false;
    const double c = cell.as<double>();
    double w = 0.0, h = 0.0;
    if (size.IsSequence() && size.size() == 2) {
      w = size[0].as<double>();
      h = size[1].as<double>();
    } else if (size.IsScalar()) {
      w = h = size.as<double>();
    } else {
      return false;
    }
    const double nodes = std::abs(w / c) * std::abs(h / c);
    return !(nodes <= kMaxGeneratedNodes);
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  CPLSetErrorHandler(CPLQuietErrorHandler);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (too_large(text)) return 0;
  try {
    sonarsynth::SimulationOverrides overrides;
    overrides.threads = 1;
    const sonarsynth::SimulationSetup setup = sonarsynth::load_simulation_from_string(
        text, "fuzz.yaml", "/nonexistent-sonarsynth-fuzz-dir", overrides);
    (void)setup;
  } catch (const sonarsynth::Error&) {
    // a clear error naming the key and the value is the expected outcome
  }
  return 0;
}
