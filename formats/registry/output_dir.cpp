// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/registry/output_dir.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace fs = std::filesystem;

namespace {

fs::path canonical_or_lexical(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) c = fs::absolute(p, ec).lexically_normal();
  if (c.filename().empty() && c.has_relative_path()) c = c.parent_path();  // "a/b/" -> "a/b"
  return c;
}

/// True if `inner` is `outer` or lies inside it (both canonical).
bool is_within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

std::string temp_prefix(const fs::path& final_dir, const char* tag) {
  std::string prefix = ".";  // appended: GCC 12 warns (-Wrestrict) on "." + string
  prefix += final_dir.filename().string();
  prefix += '.';
  prefix += tag;
  prefix += '-';
  return prefix;
}

// Temporaries of dead processes next to `final_dir`: ".NAME.part-PID" are removed;
// ".NAME.old-PID" (an old result set aside by the two-rename fallback) is put back if the final
// name is free, else removed.
void clean_stale(const fs::path& parent, const fs::path& final_dir) {
  const std::string part = temp_prefix(final_dir, "part");
  const std::string old = temp_prefix(final_dir, "old");
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const long part_pid = temporary_owner_pid(name, part, "");
    const long old_pid = temporary_owner_pid(name, old, "");
    const long pid = part_pid > 0 ? part_pid : old_pid;
    if (pid <= 0 || process_is_running(pid)) continue;
    std::error_code e2;
    if (!it->is_directory(e2) || it->is_symlink(e2)) continue;
    if (!fs::exists(it->path() / OutputDirectory::kMarkerName, e2)) continue;  // not ours
    if (old_pid > 0 && !fs::exists(fs::symlink_status(final_dir, e2))) {
      fs::rename(it->path(), final_dir, e2);
      if (!e2) continue;
    }
    fs::remove_all(it->path(), e2);
  }
}

/// The extensions of what `simulate` writes: every sonar format's (the format list, so that a
/// new format's old output is recognised) and the products'.
bool has_product_extension(const fs::path& p) {
  static const std::array<const char*, 9> kProductExt = {
      ".png", ".tif", ".tiff", ".yaml", ".xml", ".json", ".ovr", ".csv", ".geojson"};
  static const std::vector<std::string> kSonarExt = sonar_format_extensions();
  const std::string e = p.extension().string();
  for (const char* k : kProductExt) {
    if (e == k) return true;
  }
  for (const std::string& k : kSonarExt) {
    if (e == k) return true;
  }
  return false;
}

/// The label directories of `simulate` (chips/, yolo/, voc/: docs/labels.md): real directories
/// holding only real directories and files with a product extension or a label one (.txt YOLO
/// boxes, .xml VOC annotations, .yaml dataset descriptions, .jsonl chip records).
bool is_label_dir(const fs::directory_entry& d) {
  const std::string name = d.path().filename().string();
  std::error_code ec;
  if ((name != "chips" && name != "yolo" && name != "voc") || d.is_symlink(ec) ||
      !d.is_directory(ec)) {
    return false;
  }
  const auto label_extension = [](const fs::path& p) {
    const std::string e = p.extension().string();
    return e == ".txt" || e == ".xml" || e == ".yaml" || e == ".jsonl";
  };
  for (fs::recursive_directory_iterator it(d.path(), ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (it->is_symlink(e2)) return false;
    if (it->is_directory(e2)) continue;
    if (!it->is_regular_file(e2)) return false;
    if (!has_product_extension(it->path()) && !label_extension(it->path())) return false;
  }
  return !ec;
}

/// Exchanges two paths atomically; false (errno set) if the file system cannot.
bool exchange_paths(const fs::path& a, const fs::path& b) {
#ifdef RENAME_EXCHANGE
  return ::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0;
#else
  (void)a;
  (void)b;
  errno = ENOSYS;
  return false;
#endif
}

}  // namespace

std::string why_not_replaceable_output(const fs::path& dir) {
  std::error_code ec;
  bool marker = false;
  std::string foreign;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    if (name == OutputDirectory::kMarkerName) {
      marker = true;
      continue;
    }
    // Ours: a regular file (not a link) with the extension of a product.
    std::error_code e2;
    const bool ours =
        (!it->is_symlink(e2) && it->is_regular_file(e2) && has_product_extension(p)) ||
        is_label_dir(*it);
    if (!ours && foreign.empty()) {
      foreign = "it contains " + name + ", which is not a file sonarsynth writes";
    }
  }
  if (ec) return "cannot list it: " + ec.message();
  if (!foreign.empty()) return foreign;
  // Only the marker says sonarsynth made the directory: files with product names (L1.xtf,
  // effective.yaml) may be a user's own copies. An empty directory holds nothing to lose.
  const bool empty = fs::is_empty(dir, ec);
  if (empty || marker) return "";
  return "it is not a sonarsynth output directory (no " +
         std::string(OutputDirectory::kMarkerName) +
         " marker; files with product names alone do not make it one)";
}

OutputDirectory::OutputDirectory(fs::path final_dir, bool overwrite,
                                 const std::vector<fs::path>& inputs)
    : overwrite_(overwrite) {
  if (final_dir.empty()) throw FormatError("output directory: empty path");
  const fs::path given = final_dir;
  final_ = canonical_or_lexical(final_dir);
  const std::string shown = given.string();
  auto refuse = [&](const std::string& why) {
    throw FormatError(shown + ": refusing to use as the output directory: " + why);
  };
  if (final_ == final_.root_path() || final_.filename() == "." || final_.filename() == "..") {
    refuse("it is the root of the file system");
  }
  std::error_code ec;
  const fs::path cwd = canonical_or_lexical(fs::current_path(ec));
  if (!ec && is_within(cwd, final_)) {
    refuse("it is the working directory or one of its parents; replacing it would delete them");
  }
  for (const fs::path& in : inputs) {
    if (in.empty()) continue;
    if (is_within(canonical_or_lexical(in), final_)) {
      refuse("it contains the input " + in.string() + ", which replacing it would delete");
    }
  }
  const fs::path parent = final_.parent_path();
  if (!fs::is_directory(parent, ec)) {
    throw FormatError(shown + ": parent directory " + parent.string() + " does not exist");
  }
  clean_stale(parent, final_);  // may put back old results a killed run had set aside
  const auto st = fs::symlink_status(final_, ec);
  if (fs::exists(st)) {
    if (!overwrite) throw FormatError(shown + ": already exists (use --overwrite to replace it)");
    if (fs::is_symlink(st)) refuse("it is a symbolic link");
    if (!fs::is_directory(st)) refuse("it exists and is not a directory");
    const std::string why = why_not_replaceable_output(final_);
    if (!why.empty()) refuse(why + "; remove or rename it yourself, or choose another name");
  }
  temp_ = parent / (temp_prefix(final_, "part") + std::to_string(::getpid()));
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec)) {
    throw FormatError(temp_.string() + ": cannot create: " + ec.message());
  }
  register_temporary(temp_);
  std::ofstream marker(temp_ / kMarkerName);
  marker << "sonarsynth " << kVersion
         << " output directory: `sonarsynth simulate --overwrite` may replace it\n";
  if (!marker) throw FormatError((temp_ / kMarkerName).string() + ": cannot write");
}

OutputDirectory::~OutputDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
  unregister_temporary(temp_);
}

void OutputDirectory::commit() {
  std::error_code ec;
  fs::path leftover;  // the old results, to delete after the swap
  {
    const TemporariesLock lock;
    if (fs::exists(fs::symlink_status(final_, ec))) {
      if (!overwrite_) {
        throw FormatError(final_.string() + ": appeared while writing; not replaced");
      }
      const std::string why = fs::is_directory(fs::symlink_status(final_, ec))
                                  ? why_not_replaceable_output(final_)
                                  : std::string("it is not a directory");
      if (!why.empty()) {
        throw FormatError(final_.string() + ": changed while writing and is not replaced: " + why);
      }
      if (exchange_paths(temp_, final_)) {
        leftover = temp_;  // now holds the old results; still registered, so an interrupt
                           // removes it
      } else if (errno == EINVAL || errno == ENOSYS || errno == ENOTSUP) {
        const fs::path aside =
            final_.parent_path() / (temp_prefix(final_, "old") + std::to_string(::getpid()));
        register_temporary(aside);
        fs::rename(final_, aside, ec);
        if (ec) {
          unregister_temporary(aside);
          throw FormatError(final_.string() +
                            ": cannot move the old results aside: " + ec.message());
        }
        fs::rename(temp_, final_, ec);
        if (ec) {
          std::error_code back;
          fs::rename(aside, final_, back);
          unregister_temporary(aside);
          throw FormatError(final_.string() +
                            ": cannot move the results into place: " + ec.message());
        }
        unregister_temporary(temp_);
        leftover = aside;
      } else {
        throw FormatError(final_.string() + ": cannot replace: " + std::strerror(errno));
      }
    } else {
      fs::rename(temp_, final_, ec);
      if (ec) {
        throw FormatError(final_.string() +
                          ": cannot move the results into place: " + ec.message());
      }
      unregister_temporary(temp_);
    }
    committed_ = true;
  }
  if (!leftover.empty()) {
    fs::remove_all(leftover, ec);
    unregister_temporary(leftover);
  }
}

}  // namespace sonarsynth
