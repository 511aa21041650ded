// The shading models the renderer offers, selectable at run time by name (`--shader NAME`, the panel).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace drape {

enum class Shading { Wireframe, Normal, Diffuse, Phong, Texture, Bump, Displacement, Mirror, Toon, Shadow };
inline constexpr int kShadingCount = 10;

// Every model in menu order.
const std::array<Shading, kShadingCount>& allShadings();
// Lower-case name used on the command line and in file names ("phong", "displacement", ...).
std::string_view shadingName(Shading shading);
std::optional<Shading> parseShading(std::string_view name);
// "wireframe, normal, ..." for help texts and error messages.
std::string shadingNames();

}  // namespace drape
