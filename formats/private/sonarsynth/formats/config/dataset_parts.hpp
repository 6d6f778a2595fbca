// SPDX-License-Identifier: MIT
#pragma once
// Internal parts of dataset generation (include/sonarsynth/formats/config/dataset.hpp), shared
// by dataset.cpp (the items) and dataset_manifest.cpp (the manifest, summary and annotations).

#include <cstddef>
#include <filesystem>
#include <string>

namespace sonarsynth::dataset_files {

/// The whole file `p` (empty if it cannot be read).
std::string read_text(const std::filesystem::path& p);
/// Replaces `p` atomically (AtomicOutput: a hidden temporary renamed over it).
void write_atomically(const std::filesystem::path& p, const std::string& text);
/// failed/<index>.json of the dataset directory `dir`: the record of a failed item.
std::filesystem::path failure_record(const std::filesystem::path& dir, std::size_t index);

}  // namespace sonarsynth::dataset_files
