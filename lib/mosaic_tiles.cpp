// SPDX-License-Identifier: MIT
// MosaicGrid's tile store: tiles allocated on first use, spilled to a file beyond the resident
// budget and read back, and the finished image assembled from them (lib/mosaic.cpp grids the
// samples into them).
#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "sonarsynth/error.hpp"
#include "sonarsynth/mosaic.hpp"
#include "sonarsynth/spill_file.hpp"

namespace sonarsynth {
namespace {

/// The buffers of a tile, in their order in a spill slot (7 buffers of 4-byte values).
template <typename TileT>
auto tile_buffers(TileT& t) {
  return std::make_tuple(&t.sum_wi, &t.sum_w, &t.count, &t.best, &t.best_range, &t.labels,
                         &t.label_range);
}
constexpr std::size_t kTileBuffers = 7;

template <typename V>
void release(V& v) {
  V().swap(v);
}

}  // namespace

MosaicGrid::Tile& MosaicGrid::tile(std::size_t tx, std::size_t ty) {
  const std::size_t index = ty * tiles_x_ + tx;
  // Consecutive samples mostly share a tile; the cache is dropped at every ping (so last_use_
  // sees the ping) and whenever a tile is stored.
  if (index == cached_index_) return *cached_tile_;
  last_use_[index] = clock_;
  std::unique_ptr<Tile>& t = tiles_[index];
  cached_index_ = index;
  if (t) return *(cached_tile_ = t.get());
  if (spilled_[index]) {
    t = std::make_unique<Tile>(load(index));
    spilled_[index] = 0;
    resident_bytes_ += tile_bytes(*t);
    return *(cached_tile_ = t.get());
  }
  t = std::make_unique<Tile>();
  cached_tile_ = t.get();
  const std::size_t n = tile_px_ * tile_px_;
  t->count.assign(n, 0);
  switch (options_.rule) {
    case MosaicRule::weighted_mean:
      t->sum_wi.assign(n, 0.0f);
      t->sum_w.assign(n, 0.0f);
      break;
    case MosaicRule::max:
      t->best.assign(n, -std::numeric_limits<float>::infinity());
      break;
    case MosaicRule::nearest:
      t->best.assign(n, std::numeric_limits<float>::quiet_NaN());
      t->best_range.assign(n, std::numeric_limits<float>::infinity());
      break;
  }
  resident_bytes_ += tile_bytes(*t);
  return *t;
}

std::size_t MosaicGrid::tile_bytes(const Tile& t) {
  std::size_t bytes = 0;
  std::apply([&](auto*... v) { ((bytes += v->size() * 4), ...); }, tile_buffers(t));
  return bytes;
}

void MosaicGrid::spill_to(const std::filesystem::path& dir, std::size_t resident_bytes) {
  spill_ = std::make_unique<detail::SpillFile>(dir, "mosaic");
  resident_budget_ = resident_bytes;
}

std::filesystem::path MosaicGrid::spill_path() const {
  return spill_ ? spill_->path() : std::filesystem::path();
}

void MosaicGrid::store(std::size_t index) {
  cached_index_ = kNoTile;
  Tile& t = *tiles_[index];
  const std::size_t slot_bytes = kTileBuffers * 4 * tile_px_ * tile_px_;
  std::uint8_t mask = 0x80;
  std::size_t k = 0;
  std::apply(
      [&](auto*... v) {
        (
            [&] {
              if (!v->empty()) {
                spill_->write(index * slot_bytes + k * 4 * tile_px_ * tile_px_, v->data(),
                              4 * v->size());
                mask = static_cast<std::uint8_t>(mask | (1u << k));
              }
              ++k;
            }(),
            ...);
      },
      tile_buffers(t));
  resident_bytes_ -= tile_bytes(t);
  spilled_[index] = mask;
  tiles_[index].reset();
  ++spill_writes_;
}

MosaicGrid::Tile MosaicGrid::load(std::size_t index) const {
  Tile t;
  const std::size_t n = tile_px_ * tile_px_;
  const std::size_t slot_bytes = kTileBuffers * 4 * n;
  const std::uint8_t mask = spilled_[index];
  std::size_t k = 0;
  std::apply(
      [&](auto*... v) {
        (
            [&] {
              if (mask & (1u << k)) {
                v->resize(n);
                spill_->read(index * slot_bytes + k * 4 * n, v->data(), 4 * n);
              }
              ++k;
            }(),
            ...);
      },
      tile_buffers(t));
  return t;
}

void MosaicGrid::enforce_budget() {
  if (!spill_) return;
  while (resident_bytes_ > resident_budget_) {
    // The least recently used tile, never one the current ping used.
    std::size_t oldest = tiles_.size();
    for (std::size_t i = 0; i < tiles_.size(); ++i) {
      if (tiles_[i] && last_use_[i] < clock_ &&
          (oldest == tiles_.size() || last_use_[i] < last_use_[oldest])) {
        oldest = i;
      }
    }
    if (oldest == tiles_.size()) return;
    store(oldest);
  }
}

std::size_t MosaicGrid::accumulator_bytes() const {
  std::size_t bytes = 0;
  for (const auto& t : tiles_) {
    if (!t) continue;
    bytes += sizeof(float) * (t->sum_wi.capacity() + t->sum_w.capacity() + t->best.capacity() +
                              t->best_range.capacity() + t->label_range.capacity()) +
             sizeof(std::uint32_t) * t->count.capacity() +
             sizeof(std::int32_t) * t->labels.capacity();
  }
  return bytes;
}

void MosaicGrid::finalize_tile(Tile& t) const {
  if (t.final) return;
  t.final = true;
  std::vector<float>& image = options_.rule == MosaicRule::weighted_mean ? t.sum_wi : t.best;
  for (std::size_t i = 0; i < t.count.size(); ++i) {
    if (t.count[i] == 0) {
      image[i] = std::numeric_limits<float>::quiet_NaN();
    } else if (options_.rule == MosaicRule::weighted_mean) {
      image[i] = t.sum_wi[i] / t.sum_w[i];
    }
  }
  release(t.sum_w);
  release(t.best_range);
  release(t.label_range);
}

template <typename T>
void MosaicGrid::copy_tile(std::size_t index, const std::vector<T>& from,
                           std::vector<T>& to) const {
  if (from.empty()) return;
  const std::size_t col0 = (index % tiles_x_) * tile_px_;
  const std::size_t row0 = (index / tiles_x_) * tile_px_;
  const std::size_t cols = std::min(tile_px_, geometry_.cols - col0);
  const std::size_t rows = std::min(tile_px_, geometry_.rows - row0);
  for (std::size_t r = 0; r < rows; ++r) {
    std::copy_n(from.begin() + static_cast<std::ptrdiff_t>(r * tile_px_), cols,
                to.begin() + static_cast<std::ptrdiff_t>((row0 + r) * geometry_.cols + col0));
  }
}

MosaicImage MosaicGrid::finish() const& {
  MosaicImage out;
  read_window(0, 0, geometry_.cols, geometry_.rows, out);
  return out;
}

void MosaicGrid::finalize() {
  for (auto& t : tiles_) {
    if (t) finalize_tile(*t);
  }
  resident_bytes_ = 0;
  for (const auto& t : tiles_) {
    if (t) resident_bytes_ += tile_bytes(*t);
  }
  cached_index_ = kNoTile;
  finalized_ = true;
}

void MosaicGrid::read_window(std::size_t col0, std::size_t row0, std::size_t cols, std::size_t rows,
                             MosaicImage& out) const {
  if (cols == 0 || rows == 0 || col0 > geometry_.cols || cols > geometry_.cols - col0 ||
      row0 > geometry_.rows || rows > geometry_.rows - row0) {
    throw std::out_of_range("mosaic: window of " + std::to_string(cols) + " x " +
                            std::to_string(rows) + " pixels at (" + std::to_string(col0) + ", " +
                            std::to_string(row0) + ") is not inside the grid");
  }
  out.geometry = geometry_;
  out.geometry.x0_m = geometry_.x0_m + static_cast<double>(col0) * geometry_.dx_m;
  out.geometry.y0_m = geometry_.y0_m + static_cast<double>(row0) * geometry_.dy_m;
  out.geometry.cols = cols;
  out.geometry.rows = rows;
  const std::size_t n = cols * rows;
  out.intensity.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.count.assign(n, 0);
  if (has_labels_) {
    out.labels.assign(n, MosaicImage::kNoLabel);
  } else {
    out.labels.clear();
  }
  const bool mean = options_.rule == MosaicRule::weighted_mean;
  Tile loaded;
  for (std::size_t ty = row0 / tile_px_; ty * tile_px_ < row0 + rows; ++ty) {
    for (std::size_t tx = col0 / tile_px_; tx * tile_px_ < col0 + cols; ++tx) {
      const std::size_t index = ty * tiles_x_ + tx;
      const Tile* t = tiles_[index].get();
      if (!t && !spilled_[index]) continue;
      if (!t || !t->final) {
        loaded = t ? *t : load(index);
        finalize_tile(loaded);
        t = &loaded;
      }
      // The part of the tile inside the window, in tile and in window coordinates.
      const std::size_t c_begin = std::max(col0, tx * tile_px_);
      const std::size_t c_end = std::min(col0 + cols, (tx + 1) * tile_px_);
      const std::size_t r_begin = std::max(row0, ty * tile_px_);
      const std::size_t r_end = std::min(row0 + rows, (ty + 1) * tile_px_);
      auto copy = [&](const auto& from, auto& to) {
        if (from.empty()) return;
        for (std::size_t r = r_begin; r < r_end; ++r) {
          const std::size_t src = (r - ty * tile_px_) * tile_px_ + (c_begin - tx * tile_px_);
          const std::size_t dst = (r - row0) * cols + (c_begin - col0);
          std::copy_n(from.begin() + static_cast<std::ptrdiff_t>(src), c_end - c_begin,
                      to.begin() + static_cast<std::ptrdiff_t>(dst));
        }
      };
      copy(mean ? t->sum_wi : t->best, out.intensity);
      copy(t->count, out.count);
      copy(t->labels, out.labels);
    }
  }
}

MosaicImage MosaicGrid::finish() && {
  // The tiles in memory are finalised in place first (the weights and ranges released), then the
  // image's buffers are filled one at a time, each tile's part released as it is copied: memory
  // peaks at the accumulators as they were (or the image and spill budget when spilling).
  for (auto& t : tiles_) {
    if (t) finalize_tile(*t);
  }
  MosaicImage out;
  out.geometry = geometry_;
  const std::size_t n = geometry_.size();
  const bool mean = options_.rule == MosaicRule::weighted_mean;
  for (int pass = 0; pass < 3; ++pass) {
    if (pass == 0) out.intensity.assign(n, std::numeric_limits<float>::quiet_NaN());
    if (pass == 1) out.count.assign(n, 0);
    if (pass == 2 && has_labels_) out.labels.assign(n, MosaicImage::kNoLabel);
    for (std::size_t i = 0; i < tiles_.size(); ++i) {
      Tile loaded;
      Tile* t = tiles_[i].get();
      if (!t) {
        if (!spilled_[i]) continue;
        loaded = load(i);
        finalize_tile(loaded);
        t = &loaded;
      }
      if (pass == 0) {
        copy_tile(i, mean ? t->sum_wi : t->best, out.intensity);
        release(mean ? t->sum_wi : t->best);
      } else if (pass == 1) {
        copy_tile(i, t->count, out.count);
        release(t->count);
      } else {
        copy_tile(i, t->labels, out.labels);
        release(t->labels);
      }
    }
  }
  tiles_.clear();
  cached_index_ = kNoTile;
  spill_.reset();  // the spill file is removed
  resident_bytes_ = 0;
  return out;
}

}  // namespace sonarsynth
