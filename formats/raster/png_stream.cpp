// SPDX-License-Identifier: MIT
// Streamed 8-bit PNG: the waterfall images (docs/benchmarks.md, "End to end with every product"
// and "The waterfall's deflate stream and the display copy's level"). libpng writes the chunks;
// the image data's zlib stream comes from ISA-L's igzip, about four times as fast as zlib's
// level 1 on these images.
#include <isa-l/igzip_lib.h>
#include <png.h>

#include <algorithm>
#include <climits>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"

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
  if (!text.empty()) png_set_text(w.png, w.info, text.data(), static_cast<int>(text.size()));
  png_write_info(w.png, w.info);  // signature, IHDR, the tEXt chunks
  return true;
}

/// One chunk of `type` ("IDAT", "IEND") holding `data`: libpng frames it (length, type, CRC).
bool png_chunk(PngWriter& w, const char* type, const std::uint8_t* data, std::size_t size) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_write_chunk(w.png, reinterpret_cast<png_const_bytep>(type), data, size);
  return true;
}

/// The image data: one zlib stream (PNG's compression method 0) over the rows, each row led by
/// its filter type byte (0: no filter; the filters cost more than they save on these images),
/// split into IDAT chunks of at most kChunkBytes.
class IdatStream {
 public:
  static constexpr std::size_t kChunkBytes = 1 << 18;

  IdatStream(PngWriter& w, const char* who, const std::string& path)
      : w_(w), who_(who), path_(path), level_buf_(ISAL_DEF_LVL3_DEFAULT), out_(kChunkBytes) {
    isal_deflate_init(&z_);
    // Level 3, ISA-L's densest: on a line's waterfall as fast as its level 1 and 9 % smaller.
    z_.level = 3;
    z_.level_buf = level_buf_.data();
    z_.level_buf_size = static_cast<std::uint32_t>(level_buf_.size());
    z_.gzip_flag = IGZIP_ZLIB;
    z_.flush = NO_FLUSH;
    reset_output();
  }

  /// Compresses `n` bytes; `last` ends the stream and writes its remaining chunks.
  void add(const std::uint8_t* data, std::size_t n, bool last) {
    z_.next_in = const_cast<std::uint8_t*>(data);  // ISA-L's struct is not const; it only reads
    z_.avail_in = static_cast<std::uint32_t>(n);
    z_.end_of_stream = last ? 1 : 0;
    for (;;) {
      const int rc = isal_deflate(&z_);
      if (rc != COMP_OK) {
        throw FormatError(std::string(who_) + ": " + path_ + ": ISA-L deflate failed (code " +
                          std::to_string(rc) + ")");
      }
      const bool done = last ? z_.internal_state.state == ZSTATE_END : z_.avail_in == 0;
      if (z_.avail_out == 0 || (done && last)) write_chunk();
      if (done) return;
    }
  }

 private:
  void reset_output() {
    z_.next_out = out_.data();
    z_.avail_out = static_cast<std::uint32_t>(out_.size());
  }
  void write_chunk() {
    const std::size_t size = out_.size() - z_.avail_out;
    if (size > 0 && !png_chunk(w_, "IDAT", out_.data(), size)) {
      throw FormatError(std::string(who_) + ": " + path_ + ": " + w_.error.message);
    }
    reset_output();
  }

  PngWriter& w_;
  const char* who_;
  const std::string& path_;
  isal_zstream z_{};
  std::vector<std::uint8_t> level_buf_;
  std::vector<std::uint8_t> out_;
};

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
  // The row as the stream holds it: filter type 0, then the pixels (r g b, or grey).
  std::vector<std::uint8_t> row(1 + cols * n_bands, std::uint8_t{0});
  IdatStream idat(w, who, final_path);
  for (std::size_t r = 0; r < rows; ++r) {
    source.next(planar.data());
    std::uint8_t* pixels = row.data() + 1;
    if (bands == 3) {  // band-sequential row -> r g b per pixel
      const std::uint8_t* red = planar.data();
      const std::uint8_t* green = red + cols;
      const std::uint8_t* blue = green + cols;
      for (std::size_t i = 0; i < cols; ++i) {
        pixels[3 * i] = red[i];
        pixels[3 * i + 1] = green[i];
        pixels[3 * i + 2] = blue[i];
      }
    } else {
      std::copy(planar.begin(), planar.end(), pixels);
    }
    idat.add(row.data(), row.size(), r + 1 == rows);
  }
  if (!png_chunk(w, "IEND", nullptr, 0)) fail(who, final_path, w.error.message);
  std::FILE* file = w.file;
  w.file = nullptr;
  if (std::fflush(file) != 0 || std::ferror(file) != 0) {
    std::fclose(file);
    fail(who, final_path, "cannot write " + temp_path);
  }
  if (std::fclose(file) != 0) fail(who, final_path, "cannot write " + temp_path);
}

}  // namespace sonarsynth::raster
