// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

namespace sonarsynth {

/// Throws InputError if an output path names the same file as one of the inputs (after
/// resolving "." / ".." and symbolic links): `waterfall a.xtf -o a.xtf --overwrite` would
/// otherwise replace the input with its own product. Empty paths and "-" are ignored.
void refuse_output_over_input(const std::vector<std::string>& outputs,
                              const std::vector<std::string>& inputs);

/// Throws InputError if two outputs name the same file (after resolving "." / ".." and symbolic
/// links, whether or not the file exists): `mosaic a.xtf -o m.tif --rgb m.tif` would otherwise
/// leave only the one written last. `names` are the argument names shown ("-o", "--rgb").
void refuse_equal_outputs(const std::vector<std::string>& outputs,
                          const std::vector<std::string>& names);

}  // namespace sonarsynth
