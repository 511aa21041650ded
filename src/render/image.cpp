#include "render/image.hpp"

#include "core/atomic_file.hpp"

// Static: the implementations stay private to this file, so they cannot clash with the copy of stb
// inside libstb that Dear ImGui's package links.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_image.h>
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

namespace drape {

Image loadImage(const std::filesystem::path& file, int channels) {
  int width = 0, height = 0, stored = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(file.string().c_str(), &width, &height, &stored, channels),
                                                 stbi_image_free);
  if (!data) {
    const char* reason = std::filesystem::exists(file) ? stbi_failure_reason() : "no such file";
    throw ImageError(file.string() + ": cannot read image: " + (reason ? reason : "unknown error"));
  }
  Image image{width, height, channels, {}};
  image.pixels.assign(data.get(), data.get() + std::size_t(width) * height * channels);
  return image;
}

namespace {

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), std::size_t(size));
}

}  // namespace

void writePng(const std::filesystem::path& file, const Image& image) {
  stbi_write_png_compression_level = 9;  // frames and README images: smaller files, still fast at these sizes
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw ImageError(file.string() + ": cannot write an empty or inconsistent image");
  // stbi_write_png does not check its fwrite calls (a full disk left a truncated PNG and exit 0), so the
  // PNG is encoded in memory and written through the checked, atomic writer.
  std::string png;
  if (!stbi_write_png_to_func(appendBytes, &png, image.width, image.height, image.channels, image.pixels.data(),
                              image.width * image.channels))
    throw ImageError(file.string() + ": cannot encode PNG");
  writeFileAtomically(file, png);
}

void flipRows(Image& image) {
  const std::size_t row = std::size_t(image.width) * image.channels;
  std::vector<std::uint8_t> scratch(row);
  for (int y = 0; y < image.height / 2; ++y) {
    std::uint8_t* top = image.pixels.data() + std::size_t(y) * row;
    std::uint8_t* bottom = image.pixels.data() + std::size_t(image.height - 1 - y) * row;
    std::memcpy(scratch.data(), top, row);
    std::memcpy(top, bottom, row);
    std::memcpy(bottom, scratch.data(), row);
  }
}

}  // namespace drape
