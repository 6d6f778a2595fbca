// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/truth_labels.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/products/mosaic_blocks.hpp"
#include "sonarsynth/formats/products/row_spool.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/mosaic.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth::labels {
namespace {

constexpr const char* kClassNames[kClassCount] = {"water_column", "seabed", "object", "shadow",
                                                  "no_seabed"};
// Display colours of the class codes (the class raster's colour table), r g b a.
constexpr std::array<short, 4> kClassColours[kClassCount] = {
    {{0, 0, 128, 255}},      // water_column
    {{194, 178, 128, 255}},  // seabed
    {{255, 0, 0, 255}},      // object
    {{64, 64, 64, 255}},     // shadow
    {{255, 0, 255, 255}},    // no_seabed
};

constexpr const char* kShadowAttribution =
    "a shadow sample belongs to the object that casts it, recorded by the renderer: the nearest "
    "object on its ray from the sensor (in a sample hidden by several, the largest id); instance "
    "0 where no object is on the ray and seabed relief alone hides it (docs/labels.md)";
constexpr const char* kInstanceCodes =
    "0 = no object (seabed, water column, no seabed, shadow not cast by an object), > 0 = the "
    "scene object with that id (class object: its echo, class shadow: the shadow it casts), "
    "4294967295 = nodata";

std::vector<std::array<short, 4>> class_colour_table() {
  std::vector<std::array<short, 4>> t(256, std::array<short, 4>{{0, 0, 0, 0}});
  std::copy(std::begin(kClassColours), std::end(kClassColours), t.begin());
  return t;
}

std::vector<std::pair<std::string, std::string>> class_band_items() {
  std::vector<std::pair<std::string, std::string>> items;
  for (std::uint8_t c = 0; c < kClassCount; ++c) {
    items.emplace_back("CLASS_" + std::to_string(c), kClassNames[c]);
  }
  items.emplace_back("CLASS_255", "nodata");
  return items;
}

// The run's items, then what a label raster says of itself: its quantity, units and codes.
MetadataItems label_items(const MetadataItems& run, const std::string& quantity,
                          const std::string& units, const MetadataItems& codes,
                          const std::string& nodata) {
  MetadataItems items = run;
  items.insert(items.end(), {{"SONARSYNTH_VERSION", kVersion},
                             {"SONARSYNTH_QUANTITY", quantity},
                             {"SONARSYNTH_UNITS", units}});
  items.insert(items.end(), codes.begin(), codes.end());
  items.insert(items.end(),
               {{"SONARSYNTH_NODATA", nodata}, {"SONARSYNTH_LABELS_DOC", "docs/labels.md"}});
  return items;
}

MetadataItems class_items(const MetadataItems& run, const std::string& quantity,
                          const std::string& nodata) {
  return label_items(run, quantity, "none (class code)",
                     {{"SONARSYNTH_CLASS_CODES", class_codes_text()}}, nodata);
}

MetadataItems instance_items(const MetadataItems& run, const std::string& quantity,
                             const std::string& nodata) {
  return label_items(run, quantity, "none (object id)",
                     {{"SONARSYNTH_INSTANCE_CODES", kInstanceCodes},
                      {"SONARSYNTH_SHADOW_ATTRIBUTION", kShadowAttribution}},
                     nodata);
}

const std::vector<std::pair<std::string, std::string>> kTiffOptions = {
    {"COMPRESS", "DEFLATE"}, {"TILED", "YES"}, {"BIGTIFF", "IF_SAFER"}};

// Spool pads: class nodata, instance nodata as its low and high 16 bits.
constexpr float kPads[3] = {255.0f, 65535.0f, 65535.0f};

/// The rows of one of the two label rasters of a line, from the spool.
class LabelRows final : public raster::RowSource {
 public:
  LabelRows(const detail::SideSpool& spool, bool instance)
      : reader_(spool, kPads), instance_(instance), row_(3 * spool.cols()) {}
  void next(void* out) override {
    if (!reader_.next(row_)) throw FormatError("label waterfall: spool file ended early");
    const std::size_t n = row_.size() / 3;
    if (instance_) {
      auto* o = static_cast<std::uint32_t*>(out);
      for (std::size_t i = 0; i < n; ++i) {
        o[i] = static_cast<std::uint32_t>(row_[n + i]) |
               (static_cast<std::uint32_t>(row_[2 * n + i]) << 16);
      }
    } else {
      auto* o = static_cast<std::uint8_t*>(out);
      for (std::size_t i = 0; i < n; ++i) o[i] = static_cast<std::uint8_t>(row_[i]);
    }
  }
  void rewind() override { reader_.rewind(); }

 private:
  detail::SideSpool::Reader reader_;
  bool instance_;
  std::vector<float> row_;
};

}  // namespace

const char* class_name(std::uint8_t code) {
  if (code < kClassCount) return kClassNames[code];
  return code == kClassNodata ? "nodata" : nullptr;
}

std::string class_codes_text() {
  std::string s;
  for (std::uint8_t c = 0; c < kClassCount; ++c) {
    s += std::to_string(c) + " = " + kClassNames[c] + ", ";
  }
  return s + "255 = nodata";
}

void side_instances(std::span<const SampleClass> cls, std::span<const std::int32_t> id,
                    std::vector<std::uint32_t>& out) {
  out.assign(cls.size(), 0);
  std::uint32_t caster = 0;  // of the current shadow run
  for (std::size_t i = 0; i < cls.size(); ++i) {
    switch (cls[i]) {
      case SampleClass::object:
        out[i] = id[i] > 0 ? static_cast<std::uint32_t>(id[i]) : 0;
        break;
      case SampleClass::shadow:
        if (id[i] >= 0) {  // the caster the renderer recorded (0: seabed relief)
          out[i] = static_cast<std::uint32_t>(id[i]);
          break;
        }
        // No caster recorded: the run rule.
        if (i == 0 || cls[i - 1] != SampleClass::shadow || id[i - 1] >= 0) {
          caster = i > 0 && cls[i - 1] == SampleClass::object && id[i - 1] > 0
                       ? static_cast<std::uint32_t>(id[i - 1])
                       : 0;
        }
        out[i] = caster;
        break;
      default:
        break;
    }
  }
}

namespace {
constexpr const char* kWaterfallLayout =
    "row = ping, columns = port far -> near | starboard near -> far, slant range (as the "
    "line's waterfall)";
}  // namespace

namespace {

/// A one-band label raster: what it says it holds, its band's name and its nodata value.
raster::RasterLabels label_raster(MetadataItems items, const char* description, double nodata) {
  raster::RasterLabels l;
  l.metadata = std::move(items);
  l.descriptions = {description};
  l.has_nodata = true;
  l.nodata = nodata;
  return l;
}

/// What a class raster says it holds: `metadata` first, then the class items.
raster::RasterLabels class_labels(const MetadataItems& metadata, const std::string& quantity,
                                  const std::string& nodata) {
  raster::RasterLabels l =
      label_raster(class_items(metadata, quantity, nodata), "class", kClassNodata);
  l.band_metadata = {class_band_items()};
  l.color_table = class_colour_table();
  return l;
}

raster::RasterLabels instance_labels(const MetadataItems& metadata, const std::string& quantity,
                                     const std::string& nodata) {
  return label_raster(instance_items(metadata, quantity, nodata), "instance", kInstanceNodata);
}

}  // namespace

raster::RasterLabels waterfall_class_labels(const MetadataItems& metadata) {
  raster::RasterLabels l =
      class_labels(metadata, "truth class of each sample (machine-learning label)",
                   "255: no sample (a shorter side's padding)");
  l.metadata.emplace_back("SONARSYNTH_WATERFALL_LAYOUT", kWaterfallLayout);
  return l;
}

raster::RasterLabels waterfall_instance_labels(const MetadataItems& metadata) {
  raster::RasterLabels l = instance_labels(
      metadata, "truth instance (object id) of each sample (machine-learning label)",
      "4294967295: no sample (a shorter side's padding)");
  l.metadata.emplace_back("SONARSYNTH_WATERFALL_LAYOUT", kWaterfallLayout);
  return l;
}

const std::vector<std::pair<std::string, std::string>>& label_tiff_options() {
  return kTiffOptions;
}

void waterfall_label_row(std::span<const float> cls, std::span<const std::int32_t> id,
                         std::uint8_t* class_out, std::uint32_t* instance_out,
                         LabelRowScratch& scratch) {
  const std::size_t cols = cls.size();
  const std::size_t side = cols / 2;
  for (std::size_t i = 0; i < cols; ++i) {
    class_out[i] = static_cast<std::uint8_t>(cls[i]);
    instance_out[i] = kInstanceNodata;
  }
  // Each side NEAR -> FAR up to its padding: port from the middle leftwards, starboard rightwards.
  for (const bool port : {true, false}) {
    scratch.cls.clear();
    scratch.id.clear();
    for (std::size_t k = 0; k < side; ++k) {
      const std::size_t c = port ? side - 1 - k : side + k;
      if (class_out[c] == kClassNodata) break;
      scratch.cls.push_back(static_cast<SampleClass>(class_out[c]));
      scratch.id.push_back(id[c]);
    }
    side_instances(scratch.cls, scratch.id, scratch.instance);
    for (std::size_t k = 0; k < scratch.instance.size(); ++k) {
      instance_out[port ? side - 1 - k : side + k] = scratch.instance[k];
    }
  }
}

LabelWaterfall::LabelWaterfall(const std::filesystem::path& spool_dir)
    : SpooledRows(std::make_unique<detail::SideSpool>(spool_dir, 3, "label waterfall")) {}

void LabelWaterfall::add_ping(std::span<const SampleClass> port_class,
                              std::span<const SampleClass> stbd_class,
                              std::span<const std::int32_t> port_id,
                              std::span<const std::int32_t> stbd_id) {
  if (port_id.size() != port_class.size() || stbd_id.size() != stbd_class.size()) {
    throw InputError("label waterfall: ping " + std::to_string(rows()) +
                     ": class and id spans of a side differ in size");
  }
  std::vector<float> values[2][3];
  std::vector<std::uint32_t> inst;
  auto fill = [&inst](std::vector<float>(&dst)[3], std::span<const SampleClass> c,
                      std::span<const std::int32_t> id) {
    side_instances(c, id, inst);
    for (std::size_t i = 0; i < c.size(); ++i) {
      dst[0].push_back(static_cast<float>(static_cast<std::uint8_t>(c[i])));
      dst[1].push_back(static_cast<float>(inst[i] & 0xFFFFu));
      dst[2].push_back(static_cast<float>(inst[i] >> 16));
    }
  };
  fill(values[0], port_class, port_id);
  fill(values[1], stbd_class, stbd_id);
  const std::span<const float> port[3] = {values[0][0], values[0][1], values[0][2]};
  const std::span<const float> stbd[3] = {values[1][0], values[1][1], values[1][2]};
  spool_->append(port, stbd);
}

void LabelWaterfall::write(const std::string& class_path, const std::string& instance_path,
                           bool overwrite, const MetadataItems& metadata) const {
  constexpr const char* kWho = "label waterfall";
  if (rows() == 0 || cols() == 0) {
    throw FormatError(std::string(kWho) + ": " + class_path + ": no ping to write");
  }
  gdal::ensure_registered();
  AtomicOutput class_out(class_path, overwrite);
  AtomicOutput instance_out(instance_path, overwrite);
  {
    LabelRows source(*spool_, false);
    raster::stream_to_file(source, cols(), rows(), 1, GDT_Byte, "GTiff",
                           class_out.temp_path().string(), kTiffOptions,
                           waterfall_class_labels(metadata), kWho, class_path);
  }
  {
    LabelRows source(*spool_, true);
    raster::stream_to_file(source, cols(), rows(), 1, GDT_UInt32, "GTiff",
                           instance_out.temp_path().string(), kTiffOptions,
                           waterfall_instance_labels(metadata), kWho, instance_path);
  }
  class_out.commit();
  instance_out.commit();
}

MosaicLabelCodes::MosaicLabelCodes(std::vector<std::int32_t> object_ids)
    : ids_(std::move(object_ids)) {
  std::sort(ids_.begin(), ids_.end());
  ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
  if (ids_.size() >= (std::size_t{1} << 27)) {
    throw InputError("truth labels: " + std::to_string(ids_.size()) +
                     " object ids. Violated constraint: < 2^27");
  }
}

void MosaicLabelCodes::encode(std::span<const SampleClass> cls, std::span<const std::int32_t> id,
                              std::vector<std::int32_t>& out) const {
  std::vector<std::uint32_t> inst;
  side_instances(cls, id, inst);
  out.resize(cls.size());
  for (std::size_t i = 0; i < cls.size(); ++i) {
    std::int32_t index = 0;
    if (inst[i] > 0) {
      const auto v = static_cast<std::int32_t>(inst[i]);
      const auto it = std::lower_bound(ids_.begin(), ids_.end(), v);
      if (it == ids_.end() || *it != v) {
        throw FormatError("truth labels: object id " + std::to_string(v) +
                          " is not an object of the scene");
      }
      index = static_cast<std::int32_t>(it - ids_.begin()) + 1;
    }
    out[i] = static_cast<std::int32_t>(static_cast<std::uint8_t>(cls[i])) + 8 * index;
  }
}

MosaicLabelCodes::Decoded MosaicLabelCodes::decode(std::int32_t code) const {
  if (code == MosaicImage::kNoLabel) return {MosaicImage::kNoLabel, kClassNodata, kInstanceNodata};
  const auto c = static_cast<std::uint8_t>(code & 7);
  const auto index = static_cast<std::size_t>(code >> 3);
  const std::int32_t object = index > 0 ? ids_[index - 1] : 0;
  const auto sc = static_cast<SampleClass>(c);
  return {sc == SampleClass::object   ? object
          : sc == SampleClass::seabed ? 0
                                      : -1,
          c, static_cast<std::uint32_t>(object)};
}

void MosaicLabelCodes::decode(std::vector<std::int32_t>& codes, std::vector<std::uint8_t>& cls,
                              std::vector<std::uint32_t>& instance) const {
  cls.resize(codes.size());
  instance.resize(codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const Decoded d = decode(codes[i]);
    codes[i] = d.label;
    cls[i] = d.cls;
    instance[i] = d.instance;
  }
}

void MosaicLabelCodes::decode_labels(std::span<std::int32_t> codes) const {
  for (std::int32_t& code : codes) code = decode(code).label;
}

void write_mosaic_label_rasters(const std::string& class_path, const std::string& instance_path,
                                const GeoFrame& frame, const MosaicGrid& grid,
                                const MosaicLabelCodes& codes, bool overwrite,
                                const MetadataItems& metadata, bool cog_layout) {
  constexpr const char* kWho = "truth mosaic labels";
  const GridGeometry& g = grid.geometry();
  gdal::ensure_registered();
  AtomicOutput class_out(class_path, overwrite);
  AtomicOutput instance_out(instance_path, overwrite);
  const std::string what = " of the sample nearest to nadir (machine-learning label)";
  // Each raster read from the grid window by window
  // (formats/private/sonarsynth/formats/products/mosaic_blocks.hpp), the codes decoded as they are
  // read.
  auto write = [&](bool instance) {
    const std::string& path = instance ? instance_path : class_path;
    gdal::DatasetPtr src = raster::grid_dataset(
        grid, 1, instance ? GDT_UInt32 : GDT_Byte,
        [&codes, instance](const MosaicImage& w, unsigned char* out, std::size_t) {
          const std::size_t n = w.intensity.size();
          auto* ids = reinterpret_cast<std::uint32_t*>(out);
          for (std::size_t i = 0; i < n; ++i) {
            const MosaicLabelCodes::Decoded d =
                codes.decode(w.labels.empty() ? MosaicImage::kNoLabel : w.labels[i]);
            if (instance) {
              ids[i] = d.instance;
            } else {
              out[i] = d.cls;
            }
          }
        });
    raster::set_georeferencing(*src, frame, g, kWho, path);
    raster::RasterLabels l =
        instance ? instance_labels(metadata, "truth instance (object id)" + what,
                                   "4294967295: no sample in the pixel")
                 : class_labels(metadata, "truth class" + what, "255: no sample in the pixel");
    raster::describe_dataset(*src, l, 1);
    // Overviews as truth_mosaic.tif's: nearest (an overview pixel is one of its source pixels,
    // class and instance of the same sample).
    const std::string temp = (instance ? instance_out : class_out).temp_path().string();
    if (cog_layout) {
      raster::copy_with_overviews(*src, "NEAREST", kTiffOptions, temp, kWho, path);
    } else {
      raster::copy_plain_with_overviews(*src, "NEAREST", kTiffOptions, temp, kWho, path);
    }
  };
  write(false);
  write(true);
  class_out.commit();
  instance_out.commit();
}

}  // namespace sonarsynth::labels
