// SPDX-License-Identifier: MIT
// Component io: a file that appears only when committed.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "sonarsynth/formats/io/atomic_file.hpp"

int main() {
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_io.txt";
  {
    sonarsynth::AtomicOutput out(path, /*overwrite=*/true);
    std::ofstream(out.temp_path()) << "sonarsynth\n";
    if (std::filesystem::exists(path)) return 1;
    out.commit();
  }
  const bool ok = std::filesystem::file_size(path) == 11;
  std::filesystem::remove(path);
  std::cout << "io: committed\n";
  return ok ? 0 : 1;
}
