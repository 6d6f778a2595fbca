// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <string>
#include <system_error>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(fs::path final_path, bool overwrite)
    : final_path_(std::move(final_path)) {
  std::error_code ec;
  if (!overwrite && fs::exists(final_path_, ec)) {
    throw FormatError(final_path_.string() + ": already exists (use --overwrite to replace it)");
  }
  fs::path dir = final_path_.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) {
    throw FormatError(final_path_.string() + ": directory " + dir.string() + " does not exist");
  }
  static std::atomic<unsigned> counter{0};
  // Hidden name in the same directory (same file system, so rename() is atomic); the extension is
  // kept so that GDAL drivers which look at it still choose the right format.
  std::string name = ".";
  name += final_path_.stem().string();
  name += ".part-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += final_path_.extension().string();
  temp_path_ = dir / name;
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
}

void AtomicOutput::commit() {
  std::error_code ec;
  fs::rename(temp_path_, final_path_, ec);
  if (ec) {
    throw FormatError(final_path_.string() +
                      ": cannot move the finished file into place: " + ec.message());
  }
  committed_ = true;
}

}  // namespace sonarsynth
