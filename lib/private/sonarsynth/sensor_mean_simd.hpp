// SPDX-License-Identifier: MIT
// The per-sample pass of the patch textures of add_sensor_mean_terms (lib/sensor_effects.cpp) in
// vector form (Highway, dispatched at run time; every target gives the scalar loop's values bit
// for bit). Internal.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sonarsynth::sensor_mean {

/// For i in [from, to): mean[i] += level[i] where mean[i] > 1000 level[i] (the echo 30 dB above
/// the term hides its texture), else level[i] ((1 - wr[i]) nodes[cell[i]] + wr[i]
/// nodes[cell[i] + 1]): the term times its texture, interpolated between range-patch nodes.
void add_textured(const double* level, const std::int64_t* cell, const double* wr,
                  const double* nodes, std::size_t from, std::size_t to, double* mean);

/// out[c] = (1 - wa) row0[c] + wa row1[c] for c in [from, to): the nodes between two
/// along-track rows.
void blend_rows(const double* row0, const double* row1, double wa, std::size_t from, std::size_t to,
                double* out);

}  // namespace sonarsynth::sensor_mean
