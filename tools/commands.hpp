// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "cli_util.hpp"

namespace sonarsynth::cli {

// One function per subcommand (tools/cmd_<name>.cpp); main.cpp lists them.
// Add yours here and in main.cpp's table.
int run_version(const std::vector<std::string>& args);
int run_simulate(const std::vector<std::string>& args);
int run_dataset(const std::vector<std::string>& args);
int run_info(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);
int run_bathy(const std::vector<std::string>& args);
int run_mosaic(const std::vector<std::string>& args);
int run_waterfall(const std::vector<std::string>& args);
int run_match(const std::vector<std::string>& args);

}  // namespace sonarsynth::cli
