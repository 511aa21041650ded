// The renderer's textures, loaded once from textures/ (made by tools/make_textures): the fabric
// colour, two height maps and the sky cube map. A missing or unreadable file throws ImageError
// naming it, rather than leaving a black cloth.
#pragma once

#include "gl/objects.hpp"

#include <filesystem>

namespace drape {

enum class HeightMap { Cobblestone, Brick };

// $DRAPE_TEXTURE_DIR when set, else the installed or the source tree's textures/ (core/data_dir.hpp).
std::filesystem::path textureDir();

struct TextureSet {
  gl::Texture fabric;       // sRGB8_A8, mipmapped, repeating
  gl::Texture cobblestone;  // R8 height, mipmapped, repeating
  gl::Texture brick;        // R8 height
  gl::Texture sky;          // sRGB8_A8 cube map

  static TextureSet load(const std::filesystem::path& dir = textureDir());
  const gl::Texture& heightMap(HeightMap map) const { return map == HeightMap::Brick ? brick : cobblestone; }
};

}  // namespace drape
