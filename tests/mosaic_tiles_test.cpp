// SPDX-License-Identifier: MIT
// The mosaic accumulators in tiles, spilled to a temporary file beyond a memory budget: the
// image must be the bits of the untiled grid (one tile covering it, never spilled), and the
// temporary file must be gone after finishing and after a failure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mosaic_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth {
namespace {

using test::survey;

void expect_same(const MosaicImage& a, const MosaicImage& b, const std::string& what) {
  test::expect_same_bits(a, b, what);
  const std::size_t gridded = test::gridded_pixels(a);
  EXPECT_GT(gridded, a.intensity.size() / 4) << what;
  EXPECT_LT(gridded, a.intensity.size()) << what;
}

TEST(MosaicTiles, SpilledTilesGiveTheUntiledImageBitForBit) {
  const auto dir = test::mosaic_temp_dir("tiles");
  const GridGeometry g = MosaicGrid::geometry_covering({-50, -40}, {50, 40}, 0.25);
  for (MosaicRule rule : {MosaicRule::weighted_mean, MosaicRule::max, MosaicRule::nearest}) {
    const std::string what = "rule " + std::to_string(static_cast<int>(rule));
    MosaicOptions o;
    o.rule = rule;
    // The untiled layout: one tile covering the grid, never spilled.
    MosaicGrid whole(g, o, nullptr, std::max(g.cols, g.rows));
    survey(whole);
    const MosaicImage reference = std::move(whole).finish();

    // 17-pixel tiles (not dividing the grid: partial tiles at the right and bottom edges) and a
    // budget of a few tiles: most tiles go to the file and come back when a line recrosses them.
    MosaicGrid tiled(g, o, nullptr, 17);
    const std::size_t budget = 4 * 17 * 17 * 20;
    tiled.spill_to(dir, budget);
    const std::filesystem::path spill = tiled.spill_path();
    ASSERT_TRUE(std::filesystem::exists(spill)) << what;
    EXPECT_EQ(spill.parent_path(), dir);
    survey(tiled);
    EXPECT_GT(tiled.spilled_tiles(), 100u) << what;
    // After a ping, at most the budget plus the tiles of that ping (a swath of 40 m crosses at
    // most ceil(40 / (17 x 0.25)) + 2 = 12 tiles along each of its two sides and the fill).
    EXPECT_LE(tiled.accumulator_bytes(), budget + 40 * 17 * 17 * 20) << what;
    const MosaicImage copied = tiled.finish();  // reads the spilled tiles, keeps the grid
    expect_same(reference, copied, what + " (copying finish)");
    const MosaicImage moved = std::move(tiled).finish();
    expect_same(reference, moved, what + " (moving finish)");
    EXPECT_FALSE(std::filesystem::exists(spill)) << what << ": spill file left after finish";
  }
  std::filesystem::remove_all(dir);
}

TEST(MosaicTiles, UntouchedTilesTakeNoMemory) {
  const GridGeometry g = MosaicGrid::geometry_covering({-500, -500}, {500, 500}, 0.5);
  MosaicGrid grid(g, MosaicOptions{});
  EXPECT_EQ(grid.accumulator_bytes(), 0u);
  std::vector<float> v(200, 1.0f);
  grid.add(test::level_ping({0.0, 0.0}, 2.0, 20.0, v, v));
  // One ping 40 m wide crosses at most 2 x 2 tiles of 128 m: far below the 2000 x 2000 grid.
  EXPECT_GT(grid.accumulator_bytes(), 0u);
  EXPECT_LE(grid.accumulator_bytes(), 4u * 256 * 256 * 12);
}

TEST(MosaicTiles, SpillFileIsRemovedAfterAFailure) {
  const auto dir = test::mosaic_temp_dir("tiles_fail");
  const GridGeometry g = MosaicGrid::geometry_covering({-50, -40}, {50, 40}, 0.25);
  std::filesystem::path spill;
  try {
    MosaicGrid grid(g, MosaicOptions{}, nullptr, 17);
    grid.spill_to(dir, 17 * 17 * 20);
    spill = grid.spill_path();
    survey(grid);
    ASSERT_GT(grid.spilled_tiles(), 0u);
    ASSERT_TRUE(std::filesystem::exists(spill));
    MosaicPing bad;  // altitude 0 on a flat bottom: InputError, the grid unwinds
    bad.slant_range_m = 10.0;
    grid.add(bad);
    FAIL() << "the bad ping was accepted";
  } catch (const InputError&) {
  }
  EXPECT_FALSE(spill.empty());
  EXPECT_FALSE(std::filesystem::exists(spill)) << "spill file left after an exception";
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_THROW(MosaicGrid(g, MosaicOptions{}).spill_to(dir / "missing", 1), FormatError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
