// The one include of the OpenGL loader (glad2, generated at build time into build/glad/include).
// Only src/gl, src/gpu and src/render include this; everything above talks to those layers.
#pragma once

#include <glad/gl.h>
