// SPDX-License-Identifier: MIT
#pragma once
// Private helper of the survey products: the machine-learning label rasters (docs/labels.md).
// A class raster (uint8, one code per pixel from the stable table below) and an instance raster
// (uint32: the object id of object pixels and of the shadow pixels attributed to an object,
// 0 elsewhere), for each line's waterfall and for the survey mosaic.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"
#include "sonarsynth/mosaic.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth {

namespace labels {

using MetadataItems = std::vector<std::pair<std::string, std::string>>;

/// Class codes: the values of SampleClass (include/sonarsynth/rendered_ping.hpp), a stable table
/// (docs/labels.md); codes are never renumbered, new classes get new codes.
inline constexpr std::uint8_t kClassCount = 5;
/// Class raster nodata: no sample (a shorter side's padding, a mosaic pixel nothing reached).
inline constexpr std::uint8_t kClassNodata = 255;
/// Instance raster nodata (where the class is nodata).
inline constexpr std::uint32_t kInstanceNodata = 0xFFFFFFFFu;

/// The name of class `code` ("water_column", "seabed", "object", "shadow", "no_seabed";
/// "nodata" for kClassNodata); nullptr for an unknown code.
const char* class_name(std::uint8_t code);
/// "0 = water_column, 1 = seabed, 2 = object, 3 = shadow, 4 = no_seabed, 255 = nodata".
std::string class_codes_text();

/// The instance of each sample of one side (NEAR -> FAR, `cls` and `id` of one size): an object
/// sample its object id (negative taken as 0); a shadow sample its id, the caster the renderer
/// records (what hides it: > 0 an object, 0 seabed relief; docs/labels.md); a shadow sample
/// without one (id < 0: truth not from the renderer) the id of the object whose samples end just
/// before its run of such samples, 0 if the run follows anything else; every other sample 0.
void side_instances(std::span<const SampleClass> cls, std::span<const std::int32_t> id,
                    std::vector<std::uint32_t>& out);

/// The class (Byte) and instance (UInt32) label rows of one waterfall row (port FAR -> NEAR |
/// starboard NEAR -> FAR, `cls.size()` = `id.size()` = 2 x side) from its class codes (255 =
/// padding, which is only ever beyond a side's last sample) and object ids: the pixels
/// LabelWaterfall writes for the same pings. `scratch` is reused between calls.
struct LabelRowScratch {
  std::vector<SampleClass> cls;
  std::vector<std::int32_t> id;
  std::vector<std::uint32_t> instance;
};
void waterfall_label_row(std::span<const float> cls, std::span<const std::int32_t> id,
                         std::uint8_t* class_out, std::uint32_t* instance_out,
                         LabelRowScratch& scratch);

/// What the line class and instance rasters say they hold (metadata, descriptions, nodata,
/// colour table), `metadata` first; and their creation options.
raster::RasterLabels waterfall_class_labels(const MetadataItems& metadata);
raster::RasterLabels waterfall_instance_labels(const MetadataItems& metadata);
const std::vector<std::pair<std::string, std::string>>& label_tiff_options();

/// Class and instance rasters of one line, rows = pings, columns as the waterfall's (port
/// FAR -> NEAR | starboard NEAR -> FAR, slant range), padding nodata. Rows are spooled to an
/// unnamed temporary file in `spool_dir` (12 bytes per sample) like TruthWaterfall's.
class LabelWaterfall : public detail::SpooledRows {
 public:
  /// spool_'s bands: class, id low 16 bits, id high 16 bits.
  explicit LabelWaterfall(const std::filesystem::path& spool_dir = {});
  void add_ping(std::span<const SampleClass> port_class, std::span<const SampleClass> stbd_class,
                std::span<const std::int32_t> port_id, std::span<const std::int32_t> stbd_id);
  /// Writes `class_path` (Byte) and `instance_path` (UInt32) GeoTIFFs without georeferencing,
  /// each under a temporary name renamed when complete; `metadata` first, then the writer's items.
  void write(const std::string& class_path, const std::string& instance_path, bool overwrite,
             const MetadataItems& metadata) const;
};

/// The single int32 label the mosaic grids per sample (MosaicPing::*_labels, nearest to nadir)
/// carrying class, object id and shadow caster together, so that class and instance rasters
/// come from the same sample: code = class + 8 x (1 + index), index into the sorted object ids
/// of the scene (0 = no object).
class MosaicLabelCodes {
 public:
  /// The ids of the scene's objects (any order, repeats allowed).
  explicit MosaicLabelCodes(std::vector<std::int32_t> object_ids);
  /// The codes of one side (NEAR -> FAR). Throws FormatError for an id not in the scene.
  void encode(std::span<const SampleClass> cls, std::span<const std::int32_t> id,
              std::vector<std::int32_t>& out) const;
  /// One gridded code decoded: the plain truth label (object id, 0 seabed, -1 none), the class
  /// and the instance; MosaicImage::kNoLabel gives kNoLabel and the nodata class and instance.
  struct Decoded {
    std::int32_t label;
    std::uint8_t cls;
    std::uint32_t instance;
  };
  Decoded decode(std::int32_t code) const;
  /// Decodes gridded codes: `codes` becomes the plain truth label again (object id, 0 seabed,
  /// -1 none; MosaicImage::kNoLabel stays), `cls` and `instance` the label rasters.
  void decode(std::vector<std::int32_t>& codes, std::vector<std::uint8_t>& cls,
              std::vector<std::uint32_t>& instance) const;
  /// The plain truth labels of gridded codes, in place (as decode() makes `codes`).
  void decode_labels(std::span<std::int32_t> codes) const;

 private:
  std::vector<std::int32_t> ids_;  ///< sorted, unique
};

/// Writes the mosaic's class (Byte) and instance (UInt32) GeoTIFFs on its grid (the frame's UTM
/// CRS, like write_mosaic), each atomically, decoding the grid's codes window by window as they
/// are written (no image in memory; a finalized grid, MosaicGrid::finalize(), is read fastest).
/// Overviews in the COG layout, or with `cog_layout` false (`--of GTiff`) plain tiled GeoTIFFs.
void write_mosaic_label_rasters(const std::string& class_path, const std::string& instance_path,
                                const GeoFrame& frame, const MosaicGrid& grid,
                                const MosaicLabelCodes& codes, bool overwrite,
                                const MetadataItems& metadata, bool cog_layout = true);

}  // namespace labels
}  // namespace sonarsynth
