// The default camera's look-ahead for `render` and `view` (render/framing.hpp): the run's first frames on
// the CPU float solver, so that the framing is a property of the scene, the same on every machine and for
// every solver (the GPU's own bits on llvmpipe, within rounding on a GPU), and the viewer's camera is
// `render`'s.
#pragma once

#include "render/framing.hpp"

#include <string>

namespace drape {

// Where the cloth goes over `frames` frames from its start, with a progress line on a terminal
// ("LABEL: framing the run 40/180, ..."). A run that blows up is framed up to the frame before.
SceneExtent lookAheadExtent(const Scene& scene, const Topology& topology, int frames, const std::string& label);

}  // namespace drape
