// SPDX-License-Identifier: MIT
// What the benchmark drivers' main() and argument loops share: the samples folder, the value
// after a flag, and an exception turned into a message on stderr with exit status 1.
#pragma once

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#ifndef SONARSYNTH_SAMPLES_DIR
#define SONARSYNTH_SAMPLES_DIR "samples"
#endif

namespace bench {

/// The value after the flag argv[i], advancing i past it. Throws when the flag is the last one.
inline std::string value_after(int& i, int argc, char** argv) {
  if (i + 1 >= argc) throw std::runtime_error(std::string("missing value after ") + argv[i]);
  return argv[++i];
}

inline int guarded_main(const char* program, int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return 1;
  }
}

}  // namespace bench
