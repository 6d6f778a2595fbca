// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/output_dir.hpp"

#include <unistd.h>

#include <string>
#include <system_error>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace fs = std::filesystem;

OutputDirectory::OutputDirectory(fs::path final_dir, bool overwrite)
    : final_(std::move(final_dir)), overwrite_(overwrite) {
  if (final_.filename().empty()) final_ = final_.parent_path();  // "out/" -> "out"
  std::error_code ec;
  if (fs::exists(final_, ec) && !overwrite) {
    throw FormatError(final_.string() + ": already exists (use --overwrite to replace it)");
  }
  fs::path parent = final_.parent_path();
  if (parent.empty()) parent = ".";
  if (!fs::is_directory(parent, ec)) {
    throw FormatError(final_.string() + ": parent directory " + parent.string() +
                      " does not exist");
  }
  std::string name = ".";
  name += final_.filename().string();
  name += ".part-";
  name += std::to_string(::getpid());
  temp_ = parent / name;
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec)) {
    throw FormatError(temp_.string() + ": cannot create: " + ec.message());
  }
}

OutputDirectory::~OutputDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
}

void OutputDirectory::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    if (!overwrite_) throw FormatError(final_.string() + ": appeared while writing; not replaced");
    fs::remove_all(final_, ec);
    if (ec) throw FormatError(final_.string() + ": cannot replace: " + ec.message());
  }
  fs::rename(temp_, final_, ec);
  if (ec)
    throw FormatError(final_.string() + ": cannot move the results into place: " + ec.message());
  committed_ = true;
}

}  // namespace sonarsynth
