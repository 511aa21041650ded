// Compiles only up to the error in its include, which must be reported there, not here.
layout(local_size_x = 1) in;

#include "broken_helper.glsl"

void main() {}
