#include "render/shading.hpp"

namespace drape {

const std::array<Shading, kShadingCount>& allShadings() {
  static const std::array<Shading, kShadingCount> all = {
      Shading::Wireframe, Shading::Normal,       Shading::Diffuse, Shading::Phong, Shading::Texture,
      Shading::Bump,      Shading::Displacement, Shading::Mirror,  Shading::Toon,  Shading::Shadow};
  return all;
}

std::string_view shadingName(Shading shading) {
  switch (shading) {
    case Shading::Wireframe:
      return "wireframe";
    case Shading::Normal:
      return "normal";
    case Shading::Diffuse:
      return "diffuse";
    case Shading::Phong:
      return "phong";
    case Shading::Texture:
      return "texture";
    case Shading::Bump:
      return "bump";
    case Shading::Displacement:
      return "displacement";
    case Shading::Mirror:
      return "mirror";
    case Shading::Toon:
      return "toon";
    case Shading::Shadow:
      return "shadow";
  }
  return "?";
}

std::optional<Shading> parseShading(std::string_view name) {
  for (Shading s : allShadings())
    if (shadingName(s) == name) return s;
  return std::nullopt;
}

std::string shadingNames() {
  std::string names;
  for (Shading s : allShadings()) {
    if (!names.empty()) names += ", ";
    names += shadingName(s);
  }
  return names;
}

}  // namespace drape
