// SPDX-License-Identifier: MIT
// The boxes and masks of the label sets: connected pieces of an instance's pixels and their
// COCO run-length encoding (docs/labels.md).
#include <algorithm>
#include <tuple>
#include <utility>

#include "sonarsynth/formats/config/label_sets.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"

namespace sonarsynth::labels {

std::size_t BoxAccumulator::root(std::size_t part) {
  while (parent_[part] != part) {
    parent_[part] = parent_[parent_[part]];
    part = parent_[part];
  }
  return part;
}

void BoxAccumulator::join(std::size_t a, std::size_t b) {
  a = root(a);
  b = root(b);
  if (a == b) return;
  if (b < a) std::swap(a, b);
  Box& keep = parts_[a];
  const Box& gone = parts_[b];
  keep.x0 = std::min(keep.x0, gone.x0);
  keep.y0 = std::min(keep.y0, gone.y0);
  keep.x1 = std::max(keep.x1, gone.x1);
  keep.y1 = std::max(keep.y1, gone.y1);
  keep.pixels += gone.pixels;
  parent_[b] = a;
}

void BoxAccumulator::add_row(std::size_t y, std::span<const std::uint8_t> cls,
                             std::span<const std::uint32_t> instance, std::size_t x_offset) {
  // Runs of this row: consecutive pixels of one (instance > 0, category).
  current_.clear();
  for (std::size_t i = 0; i < cls.size(); ++i) {
    const std::uint32_t k = instance[i];
    int category = 0;
    if (k != 0 && k != kInstanceNodata) {
      if (cls[i] == static_cast<std::uint8_t>(SampleClass::object)) category = kCategoryObject;
      if (cls[i] == static_cast<std::uint8_t>(SampleClass::shadow)) category = kCategoryShadow;
    }
    if (category == 0) continue;
    const std::size_t x = x_offset + i;
    if (!current_.empty() && current_.back().x1 == x && current_.back().instance == k &&
        current_.back().category == category) {
      ++current_.back().x1;
    } else {
      current_.push_back({x, x + 1, k, category, 0});
    }
  }
  const bool adjacent = has_previous_ && y == previous_y_ + 1 && x_offset == previous_offset_ &&
                        cls.size() == previous_width_;
  if (!adjacent) previous_.clear();
  // Each run joins the components of the runs of the previous row with its key that touch it by
  // a side or a corner (columns [x0 - 1, x1]); both rows' runs are sorted and disjoint.
  std::size_t first = 0;
  for (Run& r : current_) {
    while (first < previous_.size() && previous_[first].x1 < r.x0) ++first;
    bool joined = false;
    for (std::size_t j = first; j < previous_.size() && previous_[j].x0 <= r.x1; ++j) {
      const Run& p = previous_[j];
      if (p.instance != r.instance || p.category != r.category) continue;
      if (!joined) {
        r.part = root(p.part);
        joined = true;
      } else {
        join(r.part, p.part);
        r.part = root(r.part);
      }
    }
    if (!joined) {
      r.part = parts_.size();
      parts_.push_back({r.instance, r.category, r.x0, y, r.x0, y, 0});
      parent_.push_back(r.part);
    }
    Box& b = parts_[root(r.part)];
    b.x0 = std::min(b.x0, r.x0);
    b.x1 = std::max(b.x1, r.x1);
    b.y0 = std::min(b.y0, y);
    b.y1 = std::max(b.y1, y + 1);
    b.pixels += r.x1 - r.x0;
    runs_.push_back({{y, r.x0, r.x1}, r.part});
  }
  std::swap(previous_, current_);
  previous_y_ = y;
  previous_offset_ = x_offset;
  previous_width_ = cls.size();
  has_previous_ = true;
}

std::vector<Box> BoxAccumulator::boxes() const {
  std::vector<Box> out;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parent_[i] == i) out.push_back(parts_[i]);
  }
  std::sort(out.begin(), out.end(), [](const Box& a, const Box& b) {
    return std::tie(a.instance, a.category, a.y0, a.x0, a.y1, a.x1) <
           std::tie(b.instance, b.category, b.y0, b.x0, b.y1, b.x1);
  });
  return out;
}

std::vector<Piece> BoxAccumulator::pieces() const {
  const auto find = [this](std::size_t p) {
    while (parent_[p] != p) p = parent_[p];
    return p;
  };
  std::vector<std::size_t> index(parts_.size(), 0);
  std::vector<Piece> out;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parent_[i] != i) continue;
    index[i] = out.size();
    out.push_back({parts_[i], {}});
  }
  // Runs were recorded row by row, left to right: each piece's stay sorted by (y, x0).
  for (const auto& [run, part] : runs_) out[index[find(part)]].runs.push_back(run);
  std::sort(out.begin(), out.end(), [](const Piece& p, const Piece& q) {
    const Box &a = p.box, &b = q.box;
    return std::tie(a.instance, a.category, a.y0, a.x0, a.y1, a.x1) <
           std::tie(b.instance, b.category, b.y0, b.x0, b.y1, b.x1);
  });
  return out;
}

std::vector<std::uint64_t> coco_rle_counts(const Piece& piece, std::size_t width,
                                           std::size_t height) {
  const Box& b = piece.box;
  const std::size_t bw = b.x1 - b.x0, bh = b.y1 - b.y0;
  // The piece's pixels in its box, column-major.
  std::vector<std::uint8_t> mask(bw * bh, 0);
  for (const PixelRun& r : piece.runs) {
    for (std::size_t x = r.x0; x < r.x1; ++x) mask[(x - b.x0) * bh + (r.y - b.y0)] = 1;
  }
  // Runs of 1 in the image's column-major order (pixel index x height + y), joined across
  // columns where one ends at the bottom row and the next starts at the top.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> ones;  // [start, end)
  for (std::size_t x = 0; x < bw; ++x) {
    for (std::size_t y = 0; y < bh; ++y) {
      if (!mask[x * bh + y]) continue;
      const std::uint64_t at = static_cast<std::uint64_t>(b.x0 + x) * height + (b.y0 + y);
      if (!ones.empty() && ones.back().second == at) {
        ones.back().second = at + 1;
      } else {
        ones.push_back({at, at + 1});
      }
    }
  }
  std::vector<std::uint64_t> counts;
  std::uint64_t at = 0;
  for (const auto& [start, end] : ones) {
    counts.push_back(start - at);
    counts.push_back(end - start);
    at = end;
  }
  const std::uint64_t total = static_cast<std::uint64_t>(width) * height;
  if (at < total) counts.push_back(total - at);
  return counts;
}

}  // namespace sonarsynth::labels
