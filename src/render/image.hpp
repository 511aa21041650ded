// 8-bit images on the CPU: loading textures (stb_image) and writing screenshots and frames (PNG).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace drape {

// A texture or image file that cannot be read or written. what() names the file.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;                  // 1 (grey), 3 (RGB) or 4 (RGBA)
  std::vector<std::uint8_t> pixels;  // rows top to bottom, as image files store them

  const std::uint8_t* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * channels]; }
};

// Loads a PNG (or anything stb_image reads) converted to `channels` channels. Throws ImageError
// "<file>: cannot read image: <reason>" when the file is missing or not an image.
Image loadImage(const std::filesystem::path& file, int channels);

// Writes a PNG whole or not at all (core/atomic_file.hpp): throws OutputError naming the file when it
// cannot be written, ImageError when the image cannot be encoded.
void writePng(const std::filesystem::path& file, const Image& image);

// Turns rows bottom-to-top (glReadPixels) into top-to-bottom, in place.
void flipRows(Image& image);

}  // namespace drape
