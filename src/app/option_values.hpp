// What the shared options' values mean for a scene, apart from their CLI11 declarations (options.hpp) so
// that code applying them (the bench) need not parse CLI11's headers.
#pragma once

#include "core/scene.hpp"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace drape {

std::vector<std::string> integratorNames();  // verlet, xpbd, vbd: what --integrator takes
// The --integrator value, when given (`name` not empty), replaces the scene's simulation.integrator.
void applyIntegrator(Scene& scene, const std::string& name);

// "640x480" with both sides in [min_side, max_side]; otherwise CommandError(kExitBadInput) naming `option`.
glm::ivec2 parseSize(const std::string& option, const std::string& text, int min_side, int max_side);

}  // namespace drape
