// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {
namespace detail {
class SpillFile;
}

/// How overlapping samples are combined in a mosaic pixel. All rules work on linear intensity
/// (never dB: a dB average of single-look speckle is 2.5 dB low).
enum class MosaicRule {
  /// Weighted mean sum(w I) / sum(w). w is a swath taper: w = sin^2(pi/2 * u / f) over the
  /// nearest fraction f of the swath (u = ground range / swath width), the same mirrored over the
  /// farthest fraction f, 1 in between, and never below kMinMosaicWeight — nadir (low grazing
  /// resolution, water-column leakage) and the far edge (low SNR) yield to the mid swath of an
  /// overlapping line, as CARIS' "Swath" weighting does.
  weighted_mean,
  max,      ///< the strongest sample ("shine-through")
  nearest,  ///< the sample with the smallest ground range (nearest to nadir); first on ties
};

/// Floor of the swath taper, so pixels seen only near nadir or at the far edge keep a value.
inline constexpr double kMinMosaicWeight = 0.01;

/// Mosaic gridding parameters.
struct MosaicOptions {
  MosaicRule rule = MosaicRule::weighted_mean;
  /// Fraction of the swath tapered at each end for weighted_mean, in [0, 0.5].
  double taper_fraction = 0.1;
  /// Samples coarser than this many pixels across track are filled in between (linear
  /// interpolation of the intensity along the ground line), in (0, 1].
  double fill_step_px = 0.5;
  /// Fill between consecutive pings too (along track): points are interpolated between the
  /// previous and the current ping's ground lines at equal ground range wherever they are more
  /// than fill_step_px apart, unless the sensor moved more than max_ping_gap_m or turned more
  /// than max_ping_turn_rad (a new line, a turn or a data gap: no fill).
  bool along_track_fill = true;
  /// Fill the nadir gap: the slant-range bin holding the altitude covers the seabed from nadir
  /// out to its far edge, so the ground between nadir and the first seabed sample's centre
  /// (at most sqrt(2 H dr + dr^2), H the altitude, dr the bin) takes that sample's value instead
  /// of staying nodata. Only where the first seabed sample is that close (a seabed rising away
  /// from nadir, seen first off to the side, is left as it is).
  bool nadir_fill = true;
  /// Nadir blanking (docs/scene-format.md, `output.mosaic.nadir`): the samples whose slant range
  /// is below the seabed's at nadir plus this many metres (the first return: the pulse echoed by
  /// the seabed below the sensor) are not gridded, >= 0; 0 = none (the water column is never
  /// gridded). With nadir_fill the gap then takes the first sample beyond it.
  double nadir_blank_m = 0.0;
  double max_ping_gap_m = 5.0;      ///< > 0
  double max_ping_turn_rad = 0.35;  ///< > 0 (20 degrees)
  /// Subdivisions of each grid cell of the bathymetry profile (HeightGrid::profile), >= 1.
  int profile_subdivisions = 2;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// One ping to grid, in the local frame of a GeoFrame. Spans are borrowed for the call only.
struct MosaicPing {
  Eigen::Vector2d sensor_xy_m{0.0, 0.0};  ///< sensor (towfish) position, local frame
  /// Sensor height in the bathymetry's datum (up positive); NaN = seabed below + altitude_m.
  /// Used only with a bathymetry grid.
  double sensor_z_m = std::numeric_limits<double>::quiet_NaN();
  double heading_grid_rad = 0.0;  ///< fish heading, clockwise from grid north (not COG)
  double pitch_rad = 0.0;         ///< + nose up: the beam plane meets the seabed ahead
  double altitude_m = 0.0;        ///< sensor height above the seabed, > 0
  double slant_range_m = 0.0;     ///< slant range of the far edge of the last sample, > 0
  /// Linear intensity NEAR -> FAR; sample i covers slant range [i, i+1) * slant_range_m / n.
  std::span<const float> port;
  std::span<const float> starboard;
  /// Optional categorical truth per sample (same sizes as port/starboard, or empty), gridded
  /// with the nearest-to-nadir rule whatever `rule` is.
  std::span<const std::int32_t> port_labels;
  std::span<const std::int32_t> starboard_labels;
};

/// What MosaicGrid::add did with one ping.
struct MosaicAddStats {
  std::size_t samples_placed = 0;     ///< samples mapped to the seabed and inside the grid
  std::size_t samples_water = 0;      ///< r <= altitude (or never reaching the bathymetry)
  std::size_t samples_outside = 0;    ///< mapped outside the grid
  std::size_t fill_points = 0;        ///< interpolated points added between coarse samples
  std::size_t along_fill_points = 0;  ///< interpolated points between this ping and the last
};

/// The finished mosaic: north-up grid whose nodes are pixel centres (GDAL Area pixels).
struct MosaicImage {
  GridGeometry geometry;
  std::vector<float> intensity;      ///< linear; NaN where nothing was gridded
  std::vector<std::uint32_t> count;  ///< contributions (samples + fill points) per pixel
  /// Nearest-to-nadir truth label per pixel (empty if no ping had labels); kNoLabel = none.
  std::vector<std::int32_t> labels;
  static constexpr std::int32_t kNoLabel = std::numeric_limits<std::int32_t>::min();
};

/// Streaming mosaic accumulator: pings are added one at a time, memory is the accumulators of
/// the tiles of the grid that samples have landed in (until finish()).
class MosaicGrid {
 public:
  /// `geometry` must have dx_m > 0 and dy_m == -dx_m (north-up, square pixels). `bathymetry`
  /// (optional, borrowed, must outlive the grid) switches slant->ground correction from flat
  /// bottom to the seabed profile. Throws InputError for bad options or geometry.
  MosaicGrid(GridGeometry geometry, MosaicOptions options, const HeightGrid* bathymetry = nullptr);
  /// The same with accumulator tiles of `tile_px` x `tile_px` pixels (>= 1; the output does not
  /// depend on it).
  MosaicGrid(GridGeometry geometry, MosaicOptions options, const HeightGrid* bathymetry,
             std::size_t tile_px);
  ~MosaicGrid();
  MosaicGrid(MosaicGrid&&) noexcept;
  MosaicGrid& operator=(MosaicGrid&&) noexcept;

  /// Pixels a side of the accumulator tiles by default.
  static constexpr std::size_t kDefaultTilePx = 256;
  /// Bytes of accumulators held in memory now (tiles touched so far and not spilled).
  std::size_t accumulator_bytes() const;
  /// Bounds the accumulators held in memory: after each ping, while they exceed
  /// `resident_bytes`, the tile used least recently is written to a temporary file created in
  /// `dir` (and read back when a later ping reaches it, or by finish()). The file is removed when
  /// the grid is destroyed or finished, whatever happened. Throws FormatError naming the file if
  /// it cannot be created.
  void spill_to(const std::filesystem::path& dir, std::size_t resident_bytes);
  /// The temporary file of spill_to(), empty before.
  std::filesystem::path spill_path() const;
  /// Tiles written to the temporary file so far (counting each time).
  std::size_t spilled_tiles() const { return spill_writes_; }

  /// A north-up geometry of square `pixel_m` pixels covering [min, max] (local frame), pixel
  /// edges on multiples of pixel_m. Throws InputError for a non-finite box or > 10^5 pixels a
  /// side.
  static GridGeometry geometry_covering(const Eigen::Vector2d& min_xy_m,
                                        const Eigen::Vector2d& max_xy_m, double pixel_m);

  /// Slant -> ground range on a flat seabed: sqrt(r^2 - A^2), NaN for r <= A (water column).
  static double flat_ground_range_m(double slant_range_m, double altitude_m);

  /// Grids one ping. Throws InputError for a ping with non-finite pose, altitude <= 0 (flat
  /// bottom) or slant_range_m <= 0, or label spans of the wrong size.
  MosaicAddStats add(const MosaicPing& ping);

  /// The next ping starts a new line: no along-track fill between it and the previous one.
  void break_line();

  const GridGeometry& geometry() const { return geometry_; }
  MosaicImage finish() const&;
  /// The same image, the tiles released as it is built and the spill file removed (the grid is
  /// left empty): the tiles in memory are reduced to their image in place first, then the
  /// image's intensity, count and labels are filled one after the other, so that memory peaks at
  /// the larger of the accumulators and the image (plus the tiles not yet copied).
  MosaicImage finish() &&;

  /// Ends the gridding without building the image: the tiles in memory are converted to their
  /// final values in place (the weights and ranges released); spilled ones are converted as they
  /// are read back by read_window(). add() must not be called afterwards (std::logic_error).
  /// finish() still works after it. Idempotent.
  void finalize();
  bool finalized() const { return finalized_; }
  /// Runs of samples (the default): the points that fall in one cell one after the other are
  /// combined in registers and the cell's accumulators are read and written once per run; the
  /// operations on each accumulator and their order are those of adding point by point, so the
  /// image is the same bit for bit. false: each point is added to its tile at once (the
  /// reference the tests compare against).
  void set_sample_runs(bool on) { runs_ = on; }
  /// True if some sample had a label (the image's labels are not empty).
  bool has_labels() const { return has_labels_; }
  /// Pixels a side of the accumulator tiles.
  std::size_t tile_px() const { return tile_px_; }
  /// Columns [col0, col0 + cols) x rows [row0, row0 + rows) of the finished image (inside the
  /// grid; std::out_of_range otherwise), as finish() would give them: `out` gets the window's
  /// geometry and buffers (labels empty if !has_labels()), reusing its capacity. Reads each tile
  /// the window touches once (a spilled one from the file); memory is the window and one tile.
  /// A window aligned to tiles reads each tile of the grid once when the windows tile the image.
  void read_window(std::size_t col0, std::size_t row0, std::size_t cols, std::size_t rows,
                   MosaicImage& out) const;

 private:
  void add_side(const MosaicPing& ping, int side, std::span<const float> values,
                std::span<const std::int32_t> labels, const Eigen::Vector2d& start,
                const Eigen::Vector2d& dir, MosaicAddStats& stats);
  void ground_ranges(const MosaicPing& ping, std::size_t n, const Eigen::Vector2d& start,
                     const Eigen::Vector2d& dir);
  /// The grid cell holding a point, (row << 32) | col, or kOutside.
  std::uint64_t cell_of(const Eigen::Vector2d& p) const;
  void splat(const Eigen::Vector2d& p, double ground_m, double swath_m, float value,
             std::int32_t label, MosaicAddStats& stats) {
    accumulate(cell_of(p), ground_m, swath_m, value, label, stats);
  }
  /// Adds one sample or fill point to `cell` (kOutside: counted as outside). Consecutive points
  /// of one cell are combined in run_ and written to the tile when the cell changes.
  void accumulate(std::uint64_t cell, double ground_m, double swath_m, float value,
                  std::int32_t label, MosaicAddStats& stats);
  /// The cell of the point at ground range g on the side line being gridded (line_): the
  /// run's cell without computing it while g stays where that cell provably holds.
  std::uint64_t line_cell(double g);
  /// Loads the accumulators of `cell` into run_.
  void open_run(std::uint64_t cell);
  /// Writes run_ back to its tile (nothing if no run is open).
  void close_run();

  GridGeometry geometry_;
  MosaicOptions options_;
  const HeightGrid* bathymetry_;
  /// The accumulators of one square tile of the grid, allocated when a sample first lands in
  /// it (a survey leaves much of its bounding box untouched); only the buffers of the rule.
  struct Tile {
    std::vector<float> sum_wi;  ///< float: the image is Float32, and 8 bytes a pixel less
    std::vector<float> sum_w;
    std::vector<std::uint32_t> count;
    std::vector<float> best;        ///< max or nearest value
    std::vector<float> best_range;  ///< ground range of the nearest value
    std::vector<std::int32_t> labels;
    std::vector<float> label_range;  ///< ground range of the label
    bool final = false;              ///< finalize_tile() done: intensity in sum_wi or best
  };
  /// Tile (tx, ty) of the grid, allocated (with the accumulators' initial values) if needed.
  Tile& tile(std::size_t tx, std::size_t ty);
  /// Copies the pixels of tile `index` inside the grid from a tile buffer to an image buffer
  /// (nothing if the tile buffer is empty).
  template <typename T>
  void copy_tile(std::size_t index, const std::vector<T>& from, std::vector<T>& to) const;
  void store(std::size_t index);       ///< writes a tile to the spill file and releases it
  Tile load(std::size_t index) const;  ///< reads a spilled tile back
  /// Writes the least recently used tiles to the spill file until the rest fit the budget.
  void enforce_budget();
  /// Converts a tile to its final form in place (intensity in sum_wi or best, the rest freed).
  void finalize_tile(Tile& t) const;
  static std::size_t tile_bytes(const Tile& t);
  std::unique_ptr<detail::SpillFile> spill_;
  std::size_t resident_budget_ = 0;
  std::size_t resident_bytes_ = 0;
  std::size_t spill_writes_ = 0;
  std::uint64_t clock_ = 0;              ///< pings added
  std::vector<std::uint64_t> last_use_;  ///< per tile: clock_ of the last ping that used it
  std::vector<std::uint8_t> spilled_;    ///< per tile: 1 = in the spill file
  std::size_t tile_px_;                  ///< pixels a side of a tile
  unsigned tile_shift_ = 0;              ///< log2(tile_px_) when a power of two
  bool tile_pow2_ = false;               ///< tile_px_ is a power of two: shifts, not divisions
  static constexpr std::size_t kNoTile = static_cast<std::size_t>(-1);
  std::size_t cached_index_ = kNoTile;  ///< the tile tile() returned last (this ping), or kNoTile
  Tile* cached_tile_ = nullptr;
  std::size_t tiles_x_ = 0;
  std::size_t tiles_y_ = 0;
  std::vector<std::unique_ptr<Tile>> tiles_;  ///< row-major, null = never touched
  static constexpr std::uint64_t kOutside = ~std::uint64_t{0};
  /// The accumulators of the cell the last points fell in (open while cell != kOutside).
  struct Run {
    std::uint64_t cell = kOutside;
    Tile* tile = nullptr;
    std::size_t idx = 0;  ///< pixel in the tile
    std::uint32_t count = 0;
    float sum_wi = 0.0f, sum_w = 0.0f, best = 0.0f, best_range = 0.0f;
    bool labelled = false;  ///< label and label_range hold the tile's (its labels exist)
    std::int32_t label = 0;
    float label_range = 0.0f;
  };
  Run run_;
  /// add_side's ground line start + g dir in pixel units, u = a + b g (column, row, +0.5 for
  /// the rounding to the nearest pixel centre), and the interval [lo, safe) of g known to lie in
  /// `cell`: lo a point whose cell was computed, safe short of the next pixel edge by a margin
  /// far above the round-off of the computed position.
  struct LineCells {
    Eigen::Vector2d start{0.0, 0.0};
    Eigen::Vector2d dir{0.0, 0.0};
    double a_col = 0.0, b_col = 0.0, a_row = 0.0, b_row = 0.0;
    bool valid = false;
    double lo = 0.0, safe = 0.0;
    std::uint64_t cell = 0;
  };
  LineCells line_;
  bool runs_ = true;
  bool has_labels_ = false;  ///< some sample had a label
  bool finalized_ = false;   ///< finalize() was called
  /// A side of the last ping resampled at equal ground ranges (j + 0.5) * step (NaN = none).
  struct GroundLine {
    bool valid = false;
    Eigen::Vector2d start{0.0, 0.0};
    Eigen::Vector2d dir{0.0, 0.0};
    Eigen::Vector2d sensor{0.0, 0.0};
    double heading_rad = 0.0;
    double swath_m = 0.0;
    std::vector<float> values;
    std::vector<std::int32_t> labels;
  };
  void resample_ground_line(std::span<const float> values, std::span<const std::int32_t> labels,
                            GroundLine& line) const;
  void fill_between(const GroundLine& a, const GroundLine& b, MosaicAddStats& stats);
  GroundLine previous_[2];
  GroundLine current_;
  // Scratch reused between pings.
  std::vector<double> ground_;
  /// ground_ranges: slant range from the sensor to the seabed at nadir.
  double nadir_slant_m_ = 0.0;
  /// add_side: the sample that fills the nadir gap, and its ground range (0: no nadir fill).
  std::size_t nadir_sample_ = 0;
  double nadir_ground_m_ = 0.0;
  std::vector<ProfilePoint> profile_;
  std::vector<double> rho_m_;  ///< slant range of each profile_ point (NaN: no seabed)
};

}  // namespace sonarsynth
