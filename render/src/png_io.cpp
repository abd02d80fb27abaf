// PNG files through libpng's simplified API (no setjmp in our code). The encoder writes
// only IHDR, IDAT and IEND for an 8-bit RGBA image, with fixed settings, so the bytes
// depend only on the pixels (and the libpng/zlib versions).
#include <png.h>

#include <cctype>
#include <filesystem>
#include <string_view>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/offscreen.hpp"

namespace plastivox::render {

std::string encode_png(const std::vector<uint8_t>& rgba, int width, int height,
                       const std::string& what) {
  if (width < 1 || height < 1 || rgba.size() != static_cast<size_t>(width) * height * 4)
    throw RenderError(what + ": image buffer holds " + std::to_string(rgba.size()) +
                      " bytes, not 4 x " + std::to_string(width) + " x " + std::to_string(height));
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGBA;
  png_alloc_size_t size = 0;
  // First call sizes the buffer, second fills it.
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, rgba.data(), 0, nullptr))
    throw RenderError(what + ": PNG encoding failed: " + image.message);
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, rgba.data(), 0, nullptr))
    throw RenderError(what + ": PNG encoding failed: " + image.message);
  bytes.resize(size);
  return bytes;
}

void write_png(const std::string& path, const std::vector<uint8_t>& rgba, int width, int height) {
  const std::string bytes = encode_png(rgba, width, height, path);
  try {
    write_file_atomic(path, bytes);
  } catch (const InputError& e) {
    throw RenderError(e.what());
  }
}

Image read_png(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw RenderError(path + ": cannot read PNG: " + image.message);
  image.format = PNG_FORMAT_RGBA;
  Image out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr)) {
    png_image_free(&image);
    throw RenderError(path + ": cannot decode PNG: " + image.message);
  }
  return out;
}

bool is_png_name(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext.empty() || ext == ".png";
}

}  // namespace plastivox::render
