// SPDX-License-Identifier: MIT
// The figure of docs/labels.md: the boxes of waterfalls.coco.json and mosaic.coco.json drawn on
// the waterfall and on the mosaic display copy of a run, side by side.
//   labels_figure SCENE.yaml OUT.png [WORK_DIR]
// The scene must ask for output.labels.coco (bench/labels_figure.yaml does).
#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sonarsynth/formats/config/run_simulation.hpp"

namespace fs = std::filesystem;

namespace {

struct Image {
  std::size_t w = 0, h = 0;
  std::vector<std::uint8_t> rgb;  // band-sequential
  void set(std::size_t x, std::size_t y, const std::uint8_t c[3]) {
    if (x >= w || y >= h) return;
    for (std::size_t b = 0; b < 3; ++b) rgb[b * w * h + y * w + x] = c[b];
  }
};

Image read_rgb(const fs::path& path) {
  auto* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
  if (!ds) throw std::runtime_error("cannot open " + path.string());
  Image im;
  im.w = static_cast<std::size_t>(ds->GetRasterXSize());
  im.h = static_cast<std::size_t>(ds->GetRasterYSize());
  im.rgb.resize(3 * im.w * im.h);
  const int n = ds->GetRasterCount();
  for (int b = 0; b < 3; ++b) {
    GDALRasterBand* band = ds->GetRasterBand(n >= 3 ? b + 1 : 1);
    if (band->RasterIO(GF_Read, 0, 0, static_cast<int>(im.w), static_cast<int>(im.h),
                       im.rgb.data() + static_cast<std::size_t>(b) * im.w * im.h,
                       static_cast<int>(im.w), static_cast<int>(im.h), GDT_Byte, 0, 0,
                       nullptr) != CE_None) {
      throw std::runtime_error("cannot read " + path.string());
    }
  }
  GDALClose(ds);
  return im;
}

Image upscale(const Image& in, std::size_t k) {
  Image out{in.w * k, in.h * k, std::vector<std::uint8_t>(3 * in.w * in.h * k * k)};
  for (std::size_t b = 0; b < 3; ++b) {
    for (std::size_t y = 0; y < out.h; ++y) {
      for (std::size_t x = 0; x < out.w; ++x) {
        out.rgb[b * out.w * out.h + y * out.w + x] =
            in.rgb[b * in.w * in.h + (y / k) * in.w + x / k];
      }
    }
  }
  return out;
}

// Half the size: each pixel the mean of 2 x 2 (keeps the figure small: speckle does not
// compress).
Image halve(const Image& in) {
  Image out{in.w / 2, in.h / 2, std::vector<std::uint8_t>(3 * (in.w / 2) * (in.h / 2))};
  for (std::size_t b = 0; b < 3; ++b) {
    const std::uint8_t* p = in.rgb.data() + b * in.w * in.h;
    for (std::size_t y = 0; y < out.h; ++y) {
      for (std::size_t x = 0; x < out.w; ++x) {
        const unsigned sum = p[2 * y * in.w + 2 * x] + p[2 * y * in.w + 2 * x + 1] +
                             p[(2 * y + 1) * in.w + 2 * x] + p[(2 * y + 1) * in.w + 2 * x + 1];
        out.rgb[b * out.w * out.h + y * out.w + x] = static_cast<std::uint8_t>((sum + 2) / 4);
      }
    }
  }
  return out;
}

// The boxes of the image's annotations, scaled by k (outward), 2 pixels wide outside the box.
void draw_boxes(Image& im, const nlohmann::json& coco, double k) {
  const std::uint8_t red[3] = {255, 40, 40}, cyan[3] = {0, 230, 255};
  for (const auto& a : coco["annotations"]) {
    const std::uint8_t* c = a["category_id"] == 1 ? red : cyan;
    const double bx = a["bbox"][0], by = a["bbox"][1], bw = a["bbox"][2], bh = a["bbox"][3];
    const auto x0 = static_cast<std::size_t>(std::floor(bx * k));
    const auto y0 = static_cast<std::size_t>(std::floor(by * k));
    const auto x1 = static_cast<std::size_t>(std::ceil((bx + bw) * k));
    const auto y1 = static_cast<std::size_t>(std::ceil((by + bh) * k));
    for (std::size_t t = 1; t <= 2; ++t) {
      const std::size_t l = x0 >= t ? x0 - t : 0, top = y0 >= t ? y0 - t : 0;
      for (std::size_t x = l; x <= x1 + t - 1; ++x) {
        im.set(x, top, c);
        im.set(x, y1 + t - 1, c);
      }
      for (std::size_t y = top; y <= y1 + t - 1; ++y) {
        im.set(l, y, c);
        im.set(x1 + t - 1, y, c);
      }
    }
  }
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream is(p);
  return nlohmann::json::parse(is);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: labels_figure SCENE.yaml OUT.png [WORK_DIR]\n");
    return 2;
  }
  try {
    GDALAllRegister();
    const fs::path work = argc > 3 ? fs::path(argv[3]) : fs::temp_directory_path() / "labels_fig";
    fs::remove_all(work);
    sonarsynth::RunOptions o;
    const sonarsynth::RunResult r = sonarsynth::run_simulation(argv[1], work, o);
    const nlohmann::json wf = read_json(work / "waterfalls.coco.json");
    const nlohmann::json mo = read_json(work / "mosaic.coco.json");
    Image a = halve(read_rgb(work / wf["images"][0]["file_name"].get<std::string>()));
    draw_boxes(a, wf, 0.5);
    const Image m0 = read_rgb(work / mo["images"][0]["file_name"].get<std::string>());
    const std::size_t k = std::clamp<std::size_t>(a.h / std::max<std::size_t>(m0.h, 1), 1, 4);
    Image b = upscale(m0, k);
    draw_boxes(b, mo, static_cast<double>(k));
    constexpr std::size_t kGap = 16;
    Image out{a.w + kGap + b.w, std::max(a.h, b.h), {}};
    out.rgb.assign(3 * out.w * out.h, 255);
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t y = 0; y < a.h; ++y) {
        for (std::size_t x = 0; x < a.w; ++x) {
          out.rgb[c * out.w * out.h + y * out.w + x] = a.rgb[c * a.w * a.h + y * a.w + x];
        }
      }
      for (std::size_t y = 0; y < b.h; ++y) {
        for (std::size_t x = 0; x < b.w; ++x) {
          out.rgb[c * out.w * out.h + y * out.w + a.w + kGap + x] =
              b.rgb[c * b.w * b.h + y * b.w + x];
        }
      }
    }
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDataset* ds =
        mem->Create("", static_cast<int>(out.w), static_cast<int>(out.h), 3, GDT_Byte, nullptr);
    if (ds->RasterIO(GF_Write, 0, 0, static_cast<int>(out.w), static_cast<int>(out.h),
                     out.rgb.data(), static_cast<int>(out.w), static_cast<int>(out.h), GDT_Byte, 3,
                     nullptr, 0, 0, 0, nullptr) != CE_None) {
      throw std::runtime_error("cannot fill the figure");
    }
    GDALDataset* png = GetGDALDriverManager()->GetDriverByName("PNG")->CreateCopy(
        argv[2], ds, FALSE, nullptr, nullptr, nullptr);
    if (!png) throw std::runtime_error(std::string("cannot write ") + argv[2]);
    GDALClose(png);
    GDALClose(ds);
    std::error_code ec;
    fs::remove(std::string(argv[2]) + ".aux.xml", ec);
    std::printf("%s: waterfall %zu x %zu with %zu boxes, mosaic %zu x %zu (x%zu) with %zu boxes\n",
                argv[2], a.w, a.h, wf["annotations"].size(), m0.w, m0.h, k,
                mo["annotations"].size());
    for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "labels_figure: %s\n", e.what());
    return 1;
  }
  return 0;
}
