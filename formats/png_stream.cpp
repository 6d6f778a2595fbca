// SPDX-License-Identifier: MIT
// Streamed 8-bit PNG through libpng: the waterfall images (docs/benchmarks.md, "End to end with
// every product").
#include <png.h>

#include <algorithm>
#include <climits>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "raster_util.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth::raster {
namespace {

/// The message of the libpng error that ended a write (error_ptr of the write struct).
struct PngError {
  std::string message;
};

extern "C" void on_png_error(png_structp png, png_const_charp message) {
  static_cast<PngError*>(png_get_error_ptr(png))->message = message ? message : "libpng error";
  png_longjmp(png, 1);
}

extern "C" void on_png_warning(png_structp /*png*/, png_const_charp /*message*/) {}

/// Owns the write struct, its info struct and the file; destroys them on every exit.
struct PngWriter {
  PngError error;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  ~PngWriter() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
    if (file) std::fclose(file);
  }
};

/// The libpng calls that may fail with a longjmp, isolated in a frame that holds no object
/// with a destructor (the jump must skip none): header and text chunks, or one row, or the end.
/// Returns false after a libpng error (its message in w.error).
bool png_begin(PngWriter& w, png_uint_32 cols, png_uint_32 rows, int colour_type,
               std::vector<png_text>& text) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_init_io(w.png, w.file);
  png_set_IHDR(w.png, w.info, cols, rows, 8, colour_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // No row filter and zlib level 1: the cheapest encoding that still compresses (the filters
  // and their per-row choice cost more than they save on these images).
  png_set_filter(w.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_compression_level(w.png, 1);
  if (!text.empty()) png_set_text(w.png, w.info, text.data(), static_cast<int>(text.size()));
  png_write_info(w.png, w.info);
  return true;
}

bool png_row(PngWriter& w, const std::uint8_t* row) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_write_row(w.png, row);
  return true;
}

bool png_end(PngWriter& w) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_write_end(w.png, w.info);
  return true;
}

[[noreturn]] void fail(const char* who, const std::string& path, const std::string& message) {
  throw FormatError(std::string(who) + ": " + path + ": " + message);
}

}  // namespace

void stream_to_png(RowSource& source, std::size_t cols, std::size_t rows, int bands,
                   const std::vector<std::pair<std::string, std::string>>& metadata,
                   const std::string& temp_path, const char* who, const std::string& final_path) {
  if (bands != 1 && bands != 3) fail(who, final_path, "a PNG has 1 or 3 bands here");
  if (cols == 0 || rows == 0 || cols > PNG_UINT_31_MAX / 3 || rows > PNG_UINT_31_MAX) {
    fail(who, final_path,
         "image of " + std::to_string(cols) + " x " + std::to_string(rows) +
             " pixels cannot be written");
  }
  // One tEXt chunk per item, in key order, a later item replacing an earlier one of the same
  // key: as GDAL's PNG driver writes a dataset's metadata (WRITE_METADATA_AS_TEXT), so that
  // GDAL reads the same items back.
  std::map<std::string, std::string> items;
  for (const auto& [k, v] : metadata) {
    if (k.empty() || k.size() > 79)
      fail(who, final_path, "metadata key '" + k + "' is not 1-79 characters");
    items[k] = v;
  }
  std::vector<png_text> text;
  for (const auto& [k, v] : items) {
    png_text t{};
    t.compression = PNG_TEXT_COMPRESSION_NONE;
    t.key = const_cast<char*>(k.c_str());  // libpng's struct is not const; it only reads
    t.text = const_cast<char*>(v.c_str());
    t.text_length = v.size();
    text.push_back(t);
  }
  PngWriter w;
  w.file = std::fopen(temp_path.c_str(), "wb");
  if (!w.file) fail(who, final_path, "cannot create " + temp_path);
  w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &w.error, on_png_error, on_png_warning);
  if (w.png) w.info = png_create_info_struct(w.png);
  if (!w.png || !w.info) fail(who, final_path, "libpng cannot start a write");
  const int colour_type = bands == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY;
  if (!png_begin(w, static_cast<png_uint_32>(cols), static_cast<png_uint_32>(rows), colour_type,
                 text)) {
    fail(who, final_path, w.error.message);
  }
  const auto n_bands = static_cast<std::size_t>(bands);
  std::vector<std::uint8_t> planar(cols * n_bands);
  std::vector<std::uint8_t> pixels(bands == 3 ? cols * n_bands : 0);
  for (std::size_t r = 0; r < rows; ++r) {
    source.next(planar.data());
    const std::uint8_t* row = planar.data();
    if (bands == 3) {  // band-sequential row -> r g b per pixel
      const std::uint8_t* red = planar.data();
      const std::uint8_t* green = red + cols;
      const std::uint8_t* blue = green + cols;
      for (std::size_t i = 0; i < cols; ++i) {
        pixels[3 * i] = red[i];
        pixels[3 * i + 1] = green[i];
        pixels[3 * i + 2] = blue[i];
      }
      row = pixels.data();
    }
    if (!png_row(w, row))
      fail(who, final_path, w.error.message + " (row " + std::to_string(r) + ")");
  }
  if (!png_end(w)) fail(who, final_path, w.error.message);
  std::FILE* file = w.file;
  w.file = nullptr;
  if (std::fflush(file) != 0 || std::ferror(file) != 0) {
    std::fclose(file);
    fail(who, final_path, "cannot write " + temp_path);
  }
  if (std::fclose(file) != 0) fail(who, final_path, "cannot write " + temp_path);
}

}  // namespace sonarsynth::raster
