#include "png_file.h"

#include "slipfit/pipeline/errors.h"

#include <png.h>

#include <cstring>

namespace slipfit::pipeline::detail {

void writeRgbPng(const std::string& path, const std::vector<std::uint8_t>& rgb, int width,
                 int height) {
  if (width <= 0 || height <= 0 ||
      rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw RunError("'" + path + "': the picture's pixels do not match its size");
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  // The simplified API reports through its return value and image.message, never by longjmp
  // out of this frame; on failure it removes the file it created.
  if (!png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), width * 3, nullptr)) {
    const std::string message = image.message;
    png_image_free(&image);
    throw RunError("'" + path + "': write failed (disk full?): " + message);
  }
}

}  // namespace slipfit::pipeline::detail
