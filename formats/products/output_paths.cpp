// SPDX-License-Identifier: MIT
// Checks of output paths against the inputs and each other, before anything is written.
#include "sonarsynth/formats/products/output_paths.hpp"

#include <filesystem>
#include <system_error>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

namespace fs = std::filesystem;

void refuse_output_over_input(const std::vector<std::string>& outputs,
                              const std::vector<std::string>& inputs) {
  for (const std::string& out : outputs) {
    if (out.empty() || out == "-") continue;
    std::error_code ec;
    if (!fs::exists(out, ec)) continue;  // a new file cannot be an existing input
    for (const std::string& in : inputs) {
      if (!in.empty() && fs::equivalent(out, in, ec)) {
        throw InputError("output " + out + " is the input " + in +
                         "; refusing to replace an input with a product");
      }
    }
  }
}

void refuse_equal_outputs(const std::vector<std::string>& outputs,
                          const std::vector<std::string>& names) {
  const auto resolved = [](const std::string& p) {
    std::error_code ec;
    fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
    return ec ? fs::absolute(p, ec).lexically_normal() : r;
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      if (outputs[i].empty() || outputs[j].empty()) continue;
      if (resolved(outputs[i]) == resolved(outputs[j])) {
        throw InputError(names[j] + " " + outputs[j] + " is the same file as " + names[i] + " " +
                         outputs[i] + ". Violated constraint: every output a different file");
      }
    }
  }
}

}  // namespace sonarsynth
