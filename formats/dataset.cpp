// SPDX-License-Identifier: MIT
// Dataset generation (docs/dataset.md): each item is drawn (formats/dataset_spec.cpp), rendered
// with run_simulation into a staging directory and renamed into place when complete; the
// manifest and summary are rebuilt from the items' own records.
#include "sonarsynth/formats/dataset.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/atomic_file.hpp"
#include "sonarsynth/formats/run_simulation.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream os(p, std::ios::binary | std::ios::trunc);
  os << text;
  os.close();
  if (!os) throw FormatError(p.string() + ": cannot write");
}

// Replaces `p` atomically (AtomicOutput: a hidden temporary renamed over it).
void write_atomically(const fs::path& p, const std::string& text) {
  AtomicOutput out(p, true);
  write_text(out.temp_path(), text);
  out.commit();
}

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "host";
  std::string h(buf);
  for (char& c : h) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-')) c = '_';
  }
  return h;
}

std::string item_label(const DatasetSpec& spec, std::size_t index, std::uint64_t seed) {
  return spec.file + ": item " + std::to_string(index) + " (seed " + std::to_string(seed) + ")";
}

fs::path failure_record(const fs::path& dir, std::size_t index) {
  char name[48];
  std::snprintf(name, sizeof name, "%06zu.json", index);
  return dir / "failed" / name;
}

json record_json(const DatasetItemResult& r) {
  json j;
  j["index"] = r.index;
  j["seed"] = r.seed;
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
  }
  return j;
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
  std::error_code ec;
  fs::create_directories(dir / "items", ec);
  fs::create_directories(dir / "failed", ec);
  fs::create_directories(dir / ".work", ec);
  if (ec || !fs::is_directory(dir / "items")) {
    throw FormatError(dir.string() + ": cannot create the dataset directory");
  }
  const fs::path recorded = dir / "spec.yaml";
  if (fs::exists(recorded)) {
    if (read_text(recorded) != spec.text) {
      throw InputError(dir.string() + ": holds a dataset made from another spec (" +
                       recorded.string() + " differs from " + spec.file +
                       "); use another directory, or the same spec to resume");
    }
    return;
  }
  write_atomically(recorded, spec.text);
}

DatasetItemResult run_dataset_item(const DatasetSpec& spec, const fs::path& dir, std::size_t index,
                                   unsigned threads) {
  const auto t0 = std::chrono::steady_clock::now();
  DatasetItemResult r;
  r.index = index;
  r.seed = dataset_item_seed(spec, index);
  const fs::path final_dir = dir / dataset_item_dir(index);
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  if (fs::exists(final_dir / "item.json")) {
    r = result_from_json(json::parse(read_text(final_dir / "item.json")));
    r.status = "skipped";
    r.seconds = elapsed();
    return r;
  }
  try {
    const DatasetItemScene scene = dataset_item_scene(spec, index);
    r.object_counts = scene.object_counts;
    r.drawn_numbers = scene.drawn_numbers;
    r.drawn_names = scene.drawn_names;
    char stage_name[128];
    std::snprintf(stage_name, sizeof stage_name, "%06zu.%s.%ld", index, host_name().c_str(),
                  static_cast<long>(::getpid()));
    const StagingGuard stage(dir / ".work" / stage_name);
    fs::remove_all(stage.dir);
    fs::create_directories(stage.dir);
    const fs::path scene_path = stage.dir / "scene.yaml";
    write_text(scene_path, scene.yaml);

    RunOptions run;
    run.overrides.quality = spec.quality;
    if (threads > 0) run.overrides.threads = threads;
    run.products.mosaic = spec.mosaic;
    run.products.waterfalls = spec.waterfalls;
    run.products.truth = spec.truth;
    const fs::path run_dir = stage.dir / "item";
    const RunResult rr = run_simulation(scene_path.string(), run_dir, run);
    r.pings = rr.total_pings;
    fs::rename(scene_path, run_dir / "scene.yaml");
    std::vector<std::string> names = {"scene.yaml", "item.json"};
    for (const fs::path& f : rr.files) names.push_back(f.filename().string());
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
        write_atomically(failure_record(dir, index), record_json(r).dump() + "\n");
      } catch (const std::exception&) {
        // The exception below reports the failure anyway.
      }
    }
    const std::string msg = item_label(spec, index, r.seed) + " failed: " + e.what();
    if (dynamic_cast<const InputError*>(&e)) throw InputError(msg);
    throw FormatError(msg);
  }
  r.seconds = elapsed();
  return r;
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

DatasetRunResult run_dataset(const DatasetSpec& spec, const fs::path& dir,
                             const DatasetRunOptions& options) {
  if (options.shard_count < 1 || options.shard_index >= options.shard_count) {
    throw InputError("shard " + std::to_string(options.shard_index) + "/" +
                     std::to_string(options.shard_count) +
                     ". Violated constraint: K/N with 0 <= K < N");
  }
  const auto t0 = std::chrono::steady_clock::now();
  prepare_dataset_dir(spec, dir);
  DatasetRunResult out;
  std::vector<std::size_t> mine;
  for (std::size_t i = options.shard_index; i < spec.count; i += options.shard_count) {
    mine.push_back(i);
  }
  for (std::size_t i : mine) {
    DatasetItemResult r;
    try {
      r = run_dataset_item(spec, dir, i, options.threads);
    } catch (const Error& e) {
      r.index = i;
      r.seed = dataset_item_seed(spec, i);
      r.status = "failed";
      r.error = e.what();
    }
    (r.status == "done" ? out.done : r.status == "skipped" ? out.skipped : out.failed) += 1;
    out.items.push_back(r);
    if (options.progress) options.progress(out.items.size(), mine.size(), r);
  }
  write_dataset_manifest(spec, dir);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void write_dataset_manifest(const DatasetSpec& spec, const fs::path& dir) {
  std::ostringstream manifest;
  std::size_t done = 0, failed = 0, pending = 0;
  std::uint64_t pings = 0;
  std::map<std::string, long long> objects;
  json failures = json::array();
  for (std::size_t i = 0; i < spec.count; ++i) {
    const fs::path item = dir / dataset_item_dir(i) / "item.json";
    const fs::path failure = failure_record(dir, i);
    json j;
    if (fs::exists(item)) {
      j = json::parse(read_text(item));
      ++done;
      pings += j.value("pings", std::uint64_t{0});
      for (const auto& [type, n] : j["objects"].items()) objects[type] += n.get<long long>();
    } else if (fs::exists(failure)) {
      j = json::parse(read_text(failure));
      ++failed;
      failures.push_back({{"index", i}, {"seed", j["seed"]}, {"error", j["error"]}});
    } else {
      j = {{"index", i}, {"seed", dataset_item_seed(spec, i)}, {"status", "pending"}};
      ++pending;
    }
    manifest << j.dump() << "\n";
  }
  write_atomically(dir / "manifest.jsonl", manifest.str());
  json summary;
  summary["name"] = spec.name;
  summary["seed"] = spec.seed;
  summary["count"] = spec.count;
  summary["done"] = done;
  summary["failed"] = failed;
  summary["pending"] = pending;
  summary["pings"] = pings;
  summary["objects"] = objects;
  summary["failures"] = failures;
  write_atomically(dir / "summary.json", summary.dump(2) + "\n");
}

}  // namespace sonarsynth
