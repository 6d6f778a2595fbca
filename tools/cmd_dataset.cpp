// SPDX-License-Identifier: MIT
// `sonarsynth dataset SPEC.yaml -o DIR [--shard K/N]`: draws the spec's scenes and renders each
// into DIR/items/<index>/, resumably (docs/dataset.md).
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"

namespace sonarsynth::cli {
namespace {

const char* const kUsage =
    "usage: sonarsynth dataset SPEC.yaml -o DIR [options]\n\n"
    "Draws the scenes of a dataset spec (format: docs/dataset.md) and renders each item into\n"
    "DIR/items/<index>/ (scene.yaml, the XTF file, waterfall, truth, effective.yaml, item.json);\n"
    "every item is a pure function of (spec, seed, index), appears only when complete, and a\n"
    "rerun skips the items already done. DIR/manifest.jsonl (one line per item: index, seed,\n"
    "status, files, object counts) and DIR/summary.json are rewritten at the end.\n"
    "--shard K/N does only the items i with i % N == K (a Slurm array: K = task id); --items A:B\n"
    "only the items A to B - 1. Raising `count` in the spec grows the dataset: the items already\n"
    "done are kept (their files are checked against their sizes; --verify: their SHA-256).";

}  // namespace

int run_dataset(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string spec_path, out_dir, shard, items;
  bool quiet = false, manifest_only = false, verify = false;
  long long threads = 0;
  // clang-format off
  opts.add_options()
    ("spec", po::value(&spec_path)->required(), "dataset spec (YAML)")
    ("output,o", po::value(&out_dir)->required(), "dataset directory (created, or resumed)")
    ("shard", po::value(&shard), "K/N: only the items i with i % N == K")
    ("items", po::value(&items), "A:B: only the items A to B - 1 (A: or :B for open ends)")
    ("verify", po::bool_switch(&verify), "check the SHA-256 of every file of the items already done")
    ("threads", po::value(&threads), "threads per item (default: all cores); files are identical for any value")
    ("manifest-only", po::bool_switch(&manifest_only), "only rewrite manifest.jsonl and summary.json")
    ("quiet,q", po::bool_switch(&quiet), "no progress lines");
  // clang-format on
  po::positional_options_description pos;
  pos.add("spec", 1);
  po::variables_map vm;
  if (!parse(args, opts, pos, vm, kUsage)) return 0;

  if (out_dir.empty()) {
    throw InputError(
        "-o ''. Violated constraint: a dataset directory (an empty path would "
        "write into the working directory)");
  }
  DatasetRunOptions o;
  if (vm.count("threads")) o.threads = checked_thread_count(threads, 1);
  if (vm.count("shard")) std::tie(o.shard_index, o.shard_count) = parse_shard(shard, "--shard");
  if (vm.count("items")) std::tie(o.first_item, o.end_item) = parse_item_range(items, "--items");
  o.verify = verify;
  const DatasetSpec spec = load_dataset_spec(spec_path);
  if (manifest_only) {
    prepare_dataset_dir(spec, out_dir);
    write_dataset_manifest(spec, out_dir);
    return 0;
  }
  const double t0 = now_s();
  o.progress = [&](std::size_t done, std::size_t total, const DatasetItemResult& r) {
    if (r.status == "failed") {
      std::cerr << "error: item " << r.index << " (seed " << r.seed << "): " << r.error << "\n";
    }
    if (!r.repaired.empty()) {
      std::cerr << "warning: item " << r.index << " was damaged (" << r.repaired
                << ") and is rendered again\n";
    }
    if (quiet) return;
    std::cerr << "[" << done << "/" << total << "] item " << r.index << " " << r.status << " ("
              << std::fixed << std::setprecision(2) << r.seconds << " s, " << r.pings << " pings), "
              << std::setprecision(1) << now_s() - t0 << " s elapsed\n";
  };
  const DatasetRunResult r = run_dataset(spec, out_dir, o);
  if (!quiet) {
    std::cout << "sonarsynth dataset: " << r.items.size() << " item(s) of " << spec.count << " ("
              << r.done << " rendered, " << r.skipped << " already done, " << r.failed << " failed";
    if (r.repaired > 0) std::cout << ", " << r.repaired << " of them repaired";
    std::cout << ") in " << std::fixed << std::setprecision(2) << r.seconds << " s\n";
  }
  return r.failed == 0 ? 0 : 1;
}

}  // namespace sonarsynth::cli
