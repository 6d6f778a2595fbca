// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/io/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <system_error>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace fs = std::filesystem;

namespace {

// Never destroyed: a signal may arrive while static destructors run at exit.
struct Registry {
  std::recursive_mutex mutex;
  std::set<fs::path> paths;
};
Registry& registry() {
  static auto* r = new Registry;
  return *r;
}

bool all_digits(const std::string& s) {
  if (s.empty() || s.size() > 10) return false;
  for (const char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

// The owner of a temporary ".<stem>.part-<pid>-<n><ext>" or of one of its helper files,
// "<temporary>.<suffix>" (AtomicOutput); -1 if `name` is neither.
long owner_of_temporary_or_helper(const std::string& name, const std::string& prefix,
                                  const std::string& ext) {
  const long pid = temporary_owner_pid(name, prefix, ext);
  if (pid > 0 || ext.empty()) return pid;
  // The first "<ext>." after the prefix ends the temporary's own name: <pid>-<n> has no dot.
  const std::size_t end = name.find(ext + ".", prefix.size());
  if (end == std::string::npos || end + ext.size() + 1 >= name.size()) return -1;
  return temporary_owner_pid(name.substr(0, end + ext.size()), prefix, ext);
}

// Removes ".<stem>.part-<pid>-<n><ext>" files next to `final_path` whose process is gone, and
// their helper files.
void remove_stale_files(const fs::path& dir, const fs::path& final_path) {
  std::string prefix = ".";  // built by appending: GCC 12 warns (-Wrestrict) on "." + string
  prefix += final_path.stem().string();
  prefix += ".part-";
  const std::string ext = final_path.extension().string();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const long pid = owner_of_temporary_or_helper(name, prefix, ext);
    if (pid <= 0 || process_is_running(pid)) continue;
    std::error_code rm;
    if (it->is_regular_file(rm)) fs::remove(it->path(), rm);
  }
}

}  // namespace

void register_temporary(const fs::path& path) {
  const std::lock_guard lock(registry().mutex);
  registry().paths.insert(path);
}

void unregister_temporary(const fs::path& path) {
  const std::lock_guard lock(registry().mutex);
  registry().paths.erase(path);
}

void remove_pending_temporaries() noexcept {
  try {
    const std::lock_guard lock(registry().mutex);
    for (const fs::path& p : registry().paths) {
      // Writers may still be creating files inside a directory: retry a few times.
      for (int attempt = 0; attempt < 5; ++attempt) {
        std::error_code ec;
        fs::remove_all(p, ec);
        if (!fs::exists(fs::symlink_status(p, ec))) break;
      }
    }
    registry().paths.clear();
  } catch (...) {
    // nothing more can be done on the way out
  }
}

TemporariesLock::TemporariesLock() {
  registry().mutex.lock();
}
TemporariesLock::~TemporariesLock() {
  registry().mutex.unlock();
}

bool process_is_running(long pid) noexcept {
  if (pid <= 0) return false;
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

long temporary_owner_pid(const std::string& name, const std::string& prefix,
                         const std::string& extension) {
  if (name.size() <= prefix.size() + extension.size()) return -1;
  if (name.compare(0, prefix.size(), prefix) != 0) return -1;
  if (name.compare(name.size() - extension.size(), extension.size(), extension) != 0) return -1;
  std::string rest = name.substr(prefix.size(), name.size() - prefix.size() - extension.size());
  const std::size_t dash = rest.find('-');
  if (dash != std::string::npos) {
    if (!all_digits(rest.substr(dash + 1))) return -1;
    rest.resize(dash);
  }
  if (!all_digits(rest)) return -1;
  return std::strtol(rest.c_str(), nullptr, 10);
}

AtomicOutput::AtomicOutput(fs::path final_path, bool overwrite)
    : final_path_(std::move(final_path)) {
  std::error_code ec;
  if (fs::is_directory(final_path_, ec)) {
    throw FormatError(final_path_.string() + ": is a directory; give a file name");
  }
  if (!overwrite && fs::exists(final_path_, ec)) {
    throw FormatError(final_path_.string() + ": already exists (use --overwrite to replace it)");
  }
  fs::path dir = final_path_.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) {
    throw FormatError(final_path_.string() + ": directory " + dir.string() + " does not exist");
  }
  remove_stale_files(dir, final_path_);
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
  register_temporary(temp_path_);
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
  unregister_temporary(temp_path_);
}

void AtomicOutput::open(std::ofstream& out, std::vector<char>& buffer,
                        const std::string& who) const {
  out.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out.open(temp_path_, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw FormatError(who + ": cannot create " + temp_path_.string() + ": " + std::strerror(errno));
  }
}

void AtomicOutput::commit(std::ofstream& out, const std::string& who) {
  out.flush();
  if (!out) {
    throw FormatError(who + ": flush failed for " + temp_path_.string() + ": " +
                      std::strerror(errno));
  }
  out.close();
  if (out.fail()) throw FormatError(who + ": close failed for " + temp_path_.string());
  commit();
}

void AtomicOutput::commit() {
  const TemporariesLock lock;
  std::error_code ec;
  fs::rename(temp_path_, final_path_, ec);
  if (ec) {
    throw FormatError(final_path_.string() +
                      ": cannot move the finished file into place: " + ec.message());
  }
  committed_ = true;
  unregister_temporary(temp_path_);
}

}  // namespace sonarsynth
