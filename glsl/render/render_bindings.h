// Shader storage binding points of the shading programs, shared by C++ and GLSL. The renderer binds
// whatever buffers it draws (the solver's, its own CPU upload, a collider mesh) to these points
// before each draw; they are separate from the solver's points in shared/layout.h.
#pragma once

#define RENDER_BINDING_POSITIONS 0  // vec4 per vertex: xyz position (m)
#define RENDER_BINDING_NORMALS 1    // vec4 per vertex: xyz unit normal
#define RENDER_BINDING_TANGENTS 2   // vec4 per vertex: xyz unit tangent along +u, w bitangent sign
#define RENDER_BINDING_UVS 3        // vec2 per vertex
#define RENDER_BINDING_HEALTH 4     // uint: the solver's blow-up flags (shared/layout.h Health); nonzero hides

// Texture units, fixed per sampler so each program sets its samplers once.
#define RENDER_UNIT_TEXTURE 0
#define RENDER_UNIT_HEIGHT_MAP 1
#define RENDER_UNIT_ENVIRONMENT 2
#define RENDER_UNIT_SHADOW_MAP 3
