// SPDX-License-Identifier: MIT
// Dataset generation (docs/dataset.md): each item is drawn (formats/config/dataset_spec.cpp),
// rendered with run_simulation into a staging directory and renamed into place when complete; the
// manifest and summary are rebuilt from the items' own records.
#include "sonarsynth/formats/config/dataset.hpp"

#include <openssl/evp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset_parts.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"

namespace sonarsynth {

namespace fs = std::filesystem;

namespace dataset_files {
namespace {

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream os(p, std::ios::binary | std::ios::trunc);
  os << text;
  os.close();
  if (!os) throw FormatError(p.string() + ": cannot write");
}

}  // namespace

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces `p` atomically (AtomicOutput: a hidden temporary renamed over it).
void write_atomically(const fs::path& p, const std::string& text) {
  AtomicOutput out(p, true);
  write_text(out.temp_path(), text);
  out.commit();
}

fs::path failure_record(const fs::path& dir, std::size_t index) {
  char name[48];
  std::snprintf(name, sizeof name, "%06zu.json", index);
  return dir / "failed" / name;
}

}  // namespace dataset_files

namespace {

using nlohmann::json;
using namespace dataset_files;

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "host";
  std::string h(buf);
  for (char& c : h) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-')) c = '_';
  }
  return h;
}

// The SHA-256 of a file, lowercase hex (what `sha256sum` prints).
std::string sha256_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw FormatError(p.string() + ": cannot read");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) {
    throw FormatError("sha256: cannot initialise the digest");
  }
  std::vector<char> buf(std::size_t{1} << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > 0 && EVP_DigestUpdate(ctx.get(), buf.data(), n) != 1) {
      throw FormatError(p.string() + ": sha256 failed");
    }
  }
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_DigestFinal_ex(ctx.get(), md, &len) != 1)
    throw FormatError(p.string() + ": sha256 failed");
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < len; ++i) {
    out += hex[md[i] >> 4];
    out += hex[md[i] & 15];
  }
  return out;
}

// Every regular file under `root` (relative, '/'-separated, sorted), except `skip`.
std::vector<std::string> files_under(const fs::path& root, const std::string& skip) {
  std::vector<std::string> out;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    if (!it->is_regular_file()) continue;
    const std::string rel = fs::relative(it->path(), root).generic_string();
    if (rel != skip) out.push_back(rel);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Staging directories: "<index>.<host>.<pid>.<n>", n unique within the process, so that two
// threads of one process rendering the same item never share one.
std::string staging_name(std::size_t index) {
  static std::atomic<unsigned long long> counter{0};
  char name[160];
  std::snprintf(name, sizeof name, "%06zu.%s.%ld.%llu", index, host_name().c_str(),
                static_cast<long>(::getpid()), counter.fetch_add(1));
  return name;
}

// Removes the staging directories in `work` that this host's processes left and that no running
// process owns (a run killed with kill -9 or a power loss); those of other hosts are left alone.
void remove_orphaned_staging(const fs::path& work) {
  std::error_code ec;
  const std::string host = host_name();
  for (auto it = fs::directory_iterator(work, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    // <index>.<host>.<pid>[.<n>]; the host may contain '-' and '_' but no '.'.
    const std::size_t a = name.find('.');
    if (a == std::string::npos) continue;
    const std::size_t b = name.find('.', a + 1);
    if (b == std::string::npos || name.compare(a + 1, b - a - 1, host) != 0) continue;
    const std::size_t c = name.find('.', b + 1);
    const std::string pid_text =
        name.substr(b + 1, c == std::string::npos ? std::string::npos : c - b - 1);
    if (pid_text.empty() || !std::all_of(pid_text.begin(), pid_text.end(), ::isdigit) ||
        pid_text.size() > 9) {
      continue;
    }
    if (process_is_running(std::stol(pid_text))) continue;
    std::error_code rm;
    fs::remove_all(it->path(), rm);
  }
}

std::string item_label(const DatasetSpec& spec, std::size_t index, std::uint64_t seed) {
  return spec.file + ": item " + std::to_string(index) + " (seed " + std::to_string(seed) + ")";
}

json record_json(const DatasetItemResult& r) {
  json j;
  j["index"] = r.index;
  j["seed"] = r.seed;
  j["seed_text"] = std::to_string(r.seed);  // exact in every JSON reader (JavaScript's too)
  j["status"] = r.status == "skipped" ? std::string("done") : r.status;
  if (r.status == "failed") {
    j["error"] = r.error;
  } else {
    j["dir"] = dataset_item_dir(r.index);
    j["files"] = r.files;
    j["objects"] = r.object_counts;
    j["pings"] = r.pings;
    json drawn = json::object();
    for (const auto& [k, v] : r.drawn_numbers) drawn[k] = v;
    for (const auto& [k, v] : r.drawn_names) drawn[k] = v;
    j["drawn"] = drawn;
    if (!r.split.empty()) j["split"] = r.split;
    if (!r.file_records.empty()) {
      json records = json::array();
      for (const auto& f : r.file_records) {
        records.push_back({{"path", f.path}, {"bytes", f.bytes}, {"sha256", f.sha256}});
      }
      j["file_records"] = records;
    }
  }
  return j;
}

// failed/<index>.json of a failed item (`r.status` "failed"): the one writer of the format that
// write_dataset_manifest() reads.
void write_failure_record(const fs::path& dir, const DatasetItemResult& r) {
  write_atomically(failure_record(dir, r.index), record_json(r).dump() + "\n");
}

DatasetItemResult result_from_json(const json& j) {
  DatasetItemResult r;
  r.index = j.at("index").get<std::size_t>();
  r.seed = j.at("seed").get<std::uint64_t>();
  r.status = j.at("status").get<std::string>();
  if (j.contains("error")) r.error = j["error"].get<std::string>();
  if (j.contains("files")) r.files = j["files"].get<std::vector<std::string>>();
  if (j.contains("objects")) r.object_counts = j["objects"].get<std::map<std::string, int>>();
  if (j.contains("pings")) r.pings = j["pings"].get<std::uint64_t>();
  if (j.contains("split")) r.split = j["split"].get<std::string>();
  if (j.contains("file_records")) {
    for (const auto& f : j["file_records"]) {
      r.file_records.push_back({f.at("path").get<std::string>(), f.at("bytes").get<std::uint64_t>(),
                                f.at("sha256").get<std::string>()});
    }
  }
  if (j.contains("drawn")) {
    for (const auto& [k, v] : j["drawn"].items()) {
      if (v.is_number()) r.drawn_numbers[k] = v.get<double>();
      if (v.is_string()) r.drawn_names[k] = v.get<std::string>();
    }
  }
  return r;
}

// Removes a staging directory whatever happens to the item.
// (Registered as a temporary: the CLI's SIGINT/SIGTERM handler removes it too.)
struct StagingGuard {
  fs::path dir;
  explicit StagingGuard(fs::path d) : dir(std::move(d)) { register_temporary(dir); }
  ~StagingGuard() {
    std::error_code ec;
    fs::remove_all(dir, ec);
    unregister_temporary(dir);
  }
  StagingGuard(const StagingGuard&) = delete;
  StagingGuard& operator=(const StagingGuard&) = delete;
};

}  // namespace

std::string dataset_item_dir(std::size_t index) {
  char name[48];
  std::snprintf(name, sizeof name, "items/%06zu", index);
  return name;
}

void prepare_dataset_dir(const DatasetSpec& spec, const fs::path& dir) {
  if (dir.empty()) {
    throw InputError(
        "dataset directory: '' (an empty path). Violated constraint: a directory "
        "path (the dataset is not written into the working directory unasked)");
  }
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw InputError(dir.string() + ": exists and is not a directory (the dataset directory)");
  }
  const fs::path recorded = dir / "spec.yaml";
  if (fs::exists(recorded, ec)) {
    const std::string text = read_text(recorded);
    if (text != spec.text) {
      DatasetSpec old;
      try {
        old = load_dataset_spec_from_string(text, recorded.string());
      } catch (const Error& e) {
        throw InputError(dir.string() + ": holds a dataset whose spec cannot be read (" + e.what() +
                         "); use another directory");
      }
      if (old.identity != spec.identity) {
        throw InputError(dir.string() + ": holds a dataset made from another spec (" +
                         recorded.string() + " differs from " + spec.file +
                         " in more than `count`); use another directory, or the same spec to "
                         "resume or grow it");
      }
    }
  }
  fs::create_directories(dir / "items", ec);
  fs::create_directories(dir / "failed", ec);
  fs::create_directories(dir / ".work", ec);
  if (ec || !fs::is_directory(dir / "items")) {
    throw FormatError(dir.string() + ": cannot create the dataset directory");
  }
  remove_orphaned_staging(dir / ".work");
  // The mesh models beside the items (their scenes name them relatively): the directory is
  // complete in itself and can be moved.
  for (const DatasetObjectType& t : spec.object_types) {
    for (std::size_t i = 0; i < t.model_copies.size(); ++i) {
      const std::string model = read_text(t.model_files[i]);
      const fs::path copy = dir / t.model_copies[i];
      fs::create_directories(copy.parent_path(), ec);
      if (!fs::exists(copy, ec) || read_text(copy) != model) write_atomically(copy, model);
    }
  }
  // The same items with another count (grown or shrunk): the directory now holds this spec.
  if (!fs::exists(recorded, ec) || read_text(recorded) != spec.text) {
    write_atomically(recorded, spec.text);
  }
}

namespace {

// What is wrong with a finished item's files ("" = nothing): a file of its record missing or of
// another size, or with `verify` another SHA-256.
std::string item_damage(const fs::path& item_dir, const DatasetItemResult& r, bool verify) {
  if (r.file_records.empty()) return "";  // an item of an older version: no record to check
  for (const auto& f : r.file_records) {
    const fs::path p = item_dir / f.path;
    std::error_code ec;
    const auto bytes = fs::file_size(p, ec);
    if (ec) return p.string() + " is missing";
    if (bytes != f.bytes) {
      return p.string() + " has " + std::to_string(bytes) + " bytes, not " +
             std::to_string(f.bytes);
    }
    if (verify && sha256_of(p) != f.sha256) return p.string() + " has another SHA-256";
  }
  return "";
}

}  // namespace

DatasetItemResult run_dataset_item(const DatasetSpec& spec, const fs::path& dir, std::size_t index,
                                   unsigned threads, bool verify) {
  const auto t0 = std::chrono::steady_clock::now();
  DatasetItemResult r;
  r.index = index;
  r.seed = dataset_item_seed(spec, index);
  const fs::path final_dir = dir / dataset_item_dir(index);
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::string repaired;
  if (fs::exists(final_dir / "item.json")) {
    DatasetItemResult done = result_from_json(json::parse(read_text(final_dir / "item.json")));
    repaired = item_damage(final_dir, done, verify);
    if (repaired.empty()) {
      done.status = "skipped";
      done.seconds = elapsed();
      return done;
    }
    // Rendered again below (an item is a pure function of the spec and its index): the damaged
    // copy is moved out of items/ first, so that no reader sees it as done meanwhile.
    const fs::path aside = dir / ".work" / (staging_name(index) + ".damaged");
    std::error_code ec;
    fs::rename(final_dir, aside, ec);
    if (ec) {
      throw FormatError(final_dir.string() + ": damaged (" + repaired +
                        ") and cannot be moved aside (" + ec.message() + ")");
    }
    fs::remove_all(aside, ec);
  }
  try {
    if (index >= spec.count) {
      throw InputError(spec.file + ": item " + std::to_string(index) +
                       " is beyond count = " + std::to_string(spec.count));
    }
    const DatasetItemScene scene = dataset_item_scene(spec, index);
    r.object_counts = scene.object_counts;
    r.drawn_numbers = scene.drawn_numbers;
    r.drawn_names = scene.drawn_names;
    r.split = dataset_item_split(spec, index);
    const StagingGuard stage(dir / ".work" / staging_name(index));
    fs::remove_all(stage.dir);
    fs::create_directories(stage.dir);
    const fs::path scene_path = stage.dir / "scene.yaml";
    write_text(scene_path, scene.dataset_yaml);

    RunOptions run;
    run.overrides.quality = spec.quality;
    run.relative_files = true;
    if (threads > 0) run.overrides.threads = threads;
    run.products.mosaic = spec.mosaic;
    run.products.waterfalls = spec.waterfalls;
    run.products.truth = spec.truth;
    const fs::path run_dir = stage.dir / "item";
    const RunResult rr = run_simulation(scene_path.string(), run_dir, run);
    r.pings = rr.total_pings;
    fs::rename(scene_path, run_dir / "scene.yaml");
    for (const std::string& rel : files_under(run_dir, "")) {
      const fs::path p = run_dir / rel;
      r.file_records.push_back({rel, static_cast<std::uint64_t>(fs::file_size(p)), sha256_of(p)});
    }
    std::vector<std::string> names = {"item.json"};
    for (const auto& f : r.file_records) names.push_back(f.path);
    std::sort(names.begin(), names.end());
    for (const std::string& n : names) r.files.push_back(dataset_item_dir(index) + "/" + n);
    r.status = "done";
    write_text(run_dir / "item.json", record_json(r).dump() + "\n");
    std::error_code ec;
    fs::rename(run_dir, final_dir, ec);
    if (ec && !fs::exists(final_dir / "item.json")) {
      throw FormatError(final_dir.string() + ": cannot move the item into place (" + ec.message() +
                        ")");
    }
    // (Another worker finishing the same item first leaves its identical copy in place.)
    fs::remove(failure_record(dir, index), ec);
  } catch (const std::exception& e) {
    r.status = "failed";
    r.error = e.what();
    r.seconds = elapsed();
    std::error_code ec;
    if (fs::is_directory(dir / "failed", ec)) {
      try {
        write_failure_record(dir, r);
      } catch (const std::exception&) {
        // The exception below reports the failure anyway.
      }
    }
    const std::string msg = item_label(spec, index, r.seed) + " failed: " + e.what();
    if (dynamic_cast<const InputError*>(&e)) throw InputError(msg);
    throw FormatError(msg);
  }
  r.repaired = repaired;
  r.seconds = elapsed();
  return r;
}

void record_dataset_failure(const DatasetSpec& spec, const fs::path& dir, std::size_t index,
                            const std::string& error) {
  if (index >= spec.count) {
    throw InputError(spec.file + ": failed item " + std::to_string(index) +
                     ". Violated constraint: index < count = " + std::to_string(spec.count));
  }
  std::error_code ec;
  fs::create_directories(dir / "failed", ec);
  if (ec) {
    throw FormatError((dir / "failed").string() + ": cannot create the directory (" + ec.message() +
                      ")");
  }
  DatasetItemResult r;
  r.index = index;
  r.seed = dataset_item_seed(spec, index);
  r.status = "failed";
  r.error = error;
  write_failure_record(dir, r);
}

std::pair<std::size_t, std::size_t> parse_shard(const std::string& text, const std::string& what) {
  const std::size_t slash = text.find('/');
  std::size_t k = 0, n = 0;
  bool ok = slash != std::string::npos && slash > 0 && slash + 1 < text.size();
  if (ok) {
    const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
    ok = std::all_of(a.begin(), a.end(), ::isdigit) && std::all_of(b.begin(), b.end(), ::isdigit) &&
         a.size() < 10 && b.size() < 10;
    if (ok) {
      k = std::stoul(a);
      n = std::stoul(b);
      ok = n >= 1 && k < n;
    }
  }
  if (!ok) {
    throw InputError(what + " = '" + text + "'. Violated constraint: K/N with 0 <= K < N");
  }
  return {k, n};
}

std::pair<std::size_t, std::size_t> parse_item_range(const std::string& text,
                                                     const std::string& what) {
  const std::size_t colon = text.find(':');
  const auto number = [](const std::string& t, std::size_t& v) {
    if (t.empty() || t.size() > 9 || !std::all_of(t.begin(), t.end(), ::isdigit)) return false;
    v = std::stoul(t);
    return true;
  };
  std::size_t a = 0, b = static_cast<std::size_t>(-1);
  bool ok = colon != std::string::npos;
  if (ok) {
    const std::string lo = text.substr(0, colon), hi = text.substr(colon + 1);
    ok = (lo.empty() || number(lo, a)) && (hi.empty() || number(hi, b)) && a < b;
  }
  if (!ok) {
    throw InputError(what + " = '" + text +
                     "'. Violated constraint: A:B with 0 <= A < B (items A to B - 1; A or B may "
                     "be left out)");
  }
  return {a, b};
}

DatasetRunResult run_dataset(const DatasetSpec& spec, const fs::path& dir,
                             const DatasetRunOptions& options) {
  if (options.shard_count < 1 || options.shard_index >= options.shard_count) {
    throw InputError("shard " + std::to_string(options.shard_index) + "/" +
                     std::to_string(options.shard_count) +
                     ". Violated constraint: K/N with 0 <= K < N");
  }
  const auto t0 = std::chrono::steady_clock::now();
  DatasetRunResult out;
  std::vector<std::size_t> mine;
  const std::size_t end = std::min(options.end_item, spec.count);
  if (options.first_item >= end) {
    throw InputError("items " + std::to_string(options.first_item) + ":" +
                     (options.end_item == static_cast<std::size_t>(-1)
                          ? std::string()
                          : std::to_string(options.end_item)) +
                     ". Violated constraint: a non-empty range of items below count = " +
                     std::to_string(spec.count));
  }
  prepare_dataset_dir(spec, dir);
  for (std::size_t i = options.first_item; i < end; ++i) {
    if (i % options.shard_count == options.shard_index) mine.push_back(i);
  }
  for (std::size_t i : mine) {
    DatasetItemResult r;
    try {
      r = run_dataset_item(spec, dir, i, options.threads, options.verify);
    } catch (const Error& e) {
      r.index = i;
      r.seed = dataset_item_seed(spec, i);
      r.status = "failed";
      r.error = e.what();
    }
    (r.status == "done" ? out.done : r.status == "skipped" ? out.skipped : out.failed) += 1;
    if (!r.repaired.empty()) ++out.repaired;
    out.items.push_back(r);
    if (options.progress) options.progress(out.items.size(), mine.size(), r);
  }
  write_dataset_manifest(spec, dir);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace sonarsynth
