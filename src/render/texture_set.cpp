#include "render/texture_set.hpp"

#include "core/data_dir.hpp"
#include "render/image.hpp"

#include <array>
#include <cstdlib>
#include <string>

namespace drape {

namespace {

// Texture coordinate v = 0 is the bottom row for GL, so the image is flipped for 2D textures; cube
// faces are not, because the cube-map convention puts t = 0 at the top of each face image.
// Colour images are sRGB-encoded (sampling returns linear values); height maps are plain numbers.
gl::Texture load2D(const std::filesystem::path& file, int channels) {
  Image image = loadImage(file, channels);
  flipRows(image);
  const GLenum internal = channels == 1 ? GL_R8 : GL_SRGB8_ALPHA8;
  const GLenum format = channels == 1 ? GL_RED : GL_RGBA;
  gl::Texture texture =
      gl::Texture::create2D(image.width, image.height, internal, gl::Texture::fullMipLevels(image.width, image.height));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows of one-channel images need not be 4-byte multiples
  texture.upload2D(format, GL_UNSIGNED_BYTE, image.pixels.data());
  texture.generateMipmaps();
  texture.setSampling(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT);
  return texture;
}

gl::Texture loadCube(const std::filesystem::path& dir) {
  const std::array<const char*, 6> faces = {"px", "nx", "py", "ny", "pz", "nz"};
  std::array<Image, 6> images;
  for (int f = 0; f < 6; ++f) {
    images[f] = loadImage(dir / ("sky_" + std::string(faces[f]) + ".png"), 4);
    if (images[f].width != images[f].height || images[f].width != images[0].width)
      throw ImageError((dir / ("sky_" + std::string(faces[f]) + ".png")).string() +
                       ": cube faces must be square and of one size");
  }
  gl::Texture cube = gl::Texture::createCube(images[0].width, GL_SRGB8_ALPHA8);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (int f = 0; f < 6; ++f)
    cube.uploadCubeFace(f, GL_RGBA, GL_UNSIGNED_BYTE, images[f].pixels.data());
  cube.setSampling(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
  return cube;
}

}  // namespace

std::filesystem::path textureDir() {
  return dataDir("textures", "DRAPE_TEXTURE_DIR");
}

TextureSet TextureSet::load(const std::filesystem::path& dir) {
  TextureSet set;
  set.fabric = load2D(dir / "fabric.png", 4);
  set.cobblestone = load2D(dir / "cobblestone_height.png", 1);
  set.brick = load2D(dir / "brick_height.png", 1);
  set.sky = loadCube(dir);
  return set;
}

}  // namespace drape
