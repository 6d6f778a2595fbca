// SPDX-License-Identifier: MIT
// The dataset generator (docs/dataset.md): specs, single items and whole (sharded) runs.
#include "sonarsynth/formats/config/dataset.hpp"

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"

namespace sonarsynth::python {

namespace {

py::dict item_dict(const DatasetItemResult& r) {
  py::dict d;
  d["index"] = r.index;
  d["seed"] = r.seed;
  d["status"] = r.status;
  d["split"] = r.split;
  d["repaired"] = r.repaired;
  d["error"] = r.error;
  d["files"] = r.files;
  d["objects"] = r.object_counts;
  d["pings"] = r.pings;
  d["seconds"] = r.seconds;
  return d;
}

}  // namespace

void bind_dataset(py::module_& m) {
  py::class_<DatasetSpec>(
      m, "DatasetSpec",
      "A dataset spec (docs/dataset.md): N scenes drawn from distributions. Load it with "
      "DatasetSpec.from_file or DatasetSpec.from_yaml; errors are ValueError naming the file, "
      "the field and the value. Picklable (by its text), for Dask.")
      .def_static(
          "from_file",
          [](const std::filesystem::path& path) { return load_dataset_spec(path.string()); },
          py::arg("path"), "Reads a spec file (str or os.PathLike).")
      .def_static("from_yaml", &load_dataset_spec_from_string, py::arg("text"),
                  py::arg("name") = "spec.yaml",
                  "Reads a spec from YAML text; `name` stands for the file in messages.")
      .def_readonly("file", &DatasetSpec::file)
      .def_readonly("text", &DatasetSpec::text)
      .def_readonly("name", &DatasetSpec::name)
      .def_readonly("seed", &DatasetSpec::seed)
      .def_readonly("count", &DatasetSpec::count)
      .def(
          "item_split",
          [](const DatasetSpec& s, std::size_t i) { return dataset_item_split(s, i); },
          py::arg("index"),
          "The split of item `index`: 'train', 'val', 'test' ('' without run.split).")
      .def(
          "item_seed", [](const DatasetSpec& s, std::size_t i) { return dataset_item_seed(s, i); },
          py::arg("index"),
          "The seed of item `index`: a keyed hash of the index with the spec's seed as key.")
      .def(
          "item_scene",
          [](const DatasetSpec& s, std::size_t i) { return dataset_item_scene(s, i).yaml; },
          py::arg("index"), "The scene file (YAML text) drawn for item `index`.")
      .def(py::pickle([](const DatasetSpec& s) { return py::make_tuple(s.text, s.file); },
                      [](const py::tuple& t) {
                        return load_dataset_spec_from_string(t[0].cast<std::string>(),
                                                             t[1].cast<std::string>());
                      }));

  m.def("dataset_item_dir", &dataset_item_dir, py::arg("index"),
        "'items/000042': the directory of item `index`, relative to the dataset directory.");
  m.def("prepare_dataset_dir", &prepare_dataset_dir, py::arg("spec"), py::arg("dir"),
        "Creates the dataset directory and records the spec in it (spec.yaml); ValueError if it "
        "holds a dataset of another spec.");
  m.def(
      "run_dataset_item",
      [](const DatasetSpec& s, const std::filesystem::path& dir, std::size_t index,
         unsigned threads, bool verify) {
        DatasetItemResult r;
        {
          py::gil_scoped_release release;
          r = run_dataset_item(s, dir, index, threads, verify);
        }
        return item_dict(r);
      },
      py::arg("spec"), py::arg("dir"), py::arg("index"), py::arg("threads") = 0,
      py::arg("verify") = false,
      "Renders item `index` into `dir` (prepare_dataset_dir first), atomically; an item already "
      "there is skipped unless its files do not match its record (then it is rendered again and "
      "`repaired` says why; verify=True also checks their SHA-256). Returns {index, seed, "
      "status: done | skipped, split, repaired, files, objects (counts by type), pings, seconds "
      "(wall time, s)}. Raises ValueError / FormatError naming the "
      "index and seed if the item fails. threads: per item, 0 = all cores (the files do not "
      "depend on it). The GIL is released while rendering.");
  m.def(
      "run_dataset",
      [](const DatasetSpec& s, const std::filesystem::path& dir, unsigned threads,
         std::pair<std::size_t, std::size_t> shard, const py::object& progress,
         const py::object& item_range, bool verify) {
        DatasetRunOptions o;
        o.threads = threads;
        o.shard_index = shard.first;
        o.shard_count = shard.second;
        o.verify = verify;
        if (!item_range.is_none()) {
          const auto range = item_range.cast<std::pair<std::size_t, std::size_t>>();
          o.first_item = range.first;
          o.end_item = range.second;
        }
        if (!progress.is_none()) {
          o.progress = [&progress](std::size_t done, std::size_t total,
                                   const DatasetItemResult& r) {
            py::gil_scoped_acquire acquire;
            progress(done, total, item_dict(r));
          };
        }
        DatasetRunResult r;
        {
          py::gil_scoped_release release;
          r = run_dataset(s, dir, o);
        }
        py::dict d;
        py::list items;
        for (const auto& i : r.items) items.append(item_dict(i));
        d["items"] = items;
        d["done"] = r.done;
        d["skipped"] = r.skipped;
        d["failed"] = r.failed;
        d["repaired"] = r.repaired;
        d["seconds"] = r.seconds;
        return d;
      },
      py::arg("spec"), py::arg("dir"), py::arg("threads") = 0,
      py::arg("shard") = std::pair<std::size_t, std::size_t>{0, 1},
      py::arg("progress") = py::none(), py::arg("items") = py::none(), py::arg("verify") = false,
      "Renders the items i with i % shard[1] == shard[0] (and items[0] <= i < items[1] when "
      "`items` is given) one after the other (what `sonarsynth "
      "dataset` does), recording a failed item and going on, then writes manifest.jsonl and "
      "summary.json (and the dataset-level annotation files). progress(done, total, item) is "
      "called after each item. Returns {items, done, skipped, failed, repaired, seconds}.");
  m.def("record_dataset_failure", &record_dataset_failure, py::arg("spec"), py::arg("dir"),
        py::arg("index"), py::arg("error"),
        "Records item `index` as failed with `error` in `dir`/failed/<index>.json, atomically: "
        "the record run_dataset_item writes for a failed item (index, seed, seed_text, status, "
        "error), which write_dataset_manifest reads and a later run of the item removes. For "
        "runners of their own (sonarsynth_dask) whose item failed outside run_dataset_item. "
        "ValueError for an index beyond count.");
  m.def("write_dataset_manifest", &write_dataset_manifest, py::arg("spec"), py::arg("dir"),
        "Rewrites manifest.jsonl and summary.json from the items' records in `dir`.");
}

}  // namespace sonarsynth::python
