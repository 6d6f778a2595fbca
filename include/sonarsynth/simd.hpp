// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace sonarsynth::simd {

/// The instruction sets the vector kernels are compiled for. `automatic` is the best the CPU
/// runs; the others cap the choice (a cap above what the CPU runs is refused), for tests that
/// compare the paths and for benchmarks and profilers (valgrind does not run AVX-512).
enum class Target { automatic, avx512, avx2, scalar };

/// "auto", "avx512", "avx2" or "scalar"; anything else throws InputError naming `what`.
Target parse_target(std::string_view name, std::string_view what = "SIMD target");

/// The name parse_target reads.
std::string_view target_name(Target t);

/// Caps the kernels at `t` for the whole process (not thread-safe against running kernels).
/// Throws InputError if the CPU cannot run `t`.
void set_target(Target t);

/// The target the kernels dispatch to now: never `automatic`.
Target active_target();

/// True if this CPU (and this build) can run `t`.
bool supported(Target t);

/// The concrete targets this CPU (and this build) runs, slowest first: scalar, then avx2 and
/// avx512 where supported. For loops that compare the paths.
std::vector<Target> supported_targets();

/// Applies the environment variable SONARSYNTH_SIMD (a parse_target name) once per process;
/// called by every entry point that runs kernels, so a benchmark or profiler run can pick the
/// path without a flag. An invalid value throws InputError naming the variable.
void configure_from_environment();

}  // namespace sonarsynth::simd
