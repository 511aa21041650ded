// Shader storage binding points of the shading programs, shared by C++ and GLSL. The renderer binds
// whatever buffers it draws (the solver's, its own CPU upload, a collider mesh) to these points
// before each draw; they are separate from the solver's points in shared/layout.h.
#pragma once

#define RENDER_BINDING_POSITIONS 0  // vec4 per vertex: xyz position (m)
#define RENDER_BINDING_NORMALS 1    // vec4 per vertex: xyz unit normal
#define RENDER_BINDING_TANGENTS 2   // vec4 per vertex: xyz unit tangent along +u, w bitangent sign
#define RENDER_BINDING_UVS 3        // vec2 per vertex
#define RENDER_BINDING_HEALTH 4     // uint: the solver's blow-up flags (shared/layout.h Health); nonzero hides
#define RENDER_BINDING_CENTRES 5    // vec4 per quad: the cloth's quad centres, vertices points + q (cloth_surface.hpp)
// The surface pass only (cloth_surface.comp): the cloth's faces and which faces each point is a corner of.
#define RENDER_BINDING_FACES 6         // uvec4 per face: corners, w = RENDER_NO_CORNER for a triangle; quads first
#define RENDER_BINDING_FACE_OFFSETS 7  // uint per point + 1: CSR offsets into the point-faces list
#define RENDER_BINDING_POINT_FACES 8   // uint: face indices
#define RENDER_BINDING_QUAD_REST 9     // vec2 per quad: rest lengths of its diagonals (corner 0-2, 1-3)

#define RENDER_NO_CORNER 0xffffffffu  // kNoCorner (core/cloth_mesh.hpp)
#define RENDER_SURFACE_LOCAL_SIZE 64

// Texture units, fixed per sampler so each program sets its samplers once.
#define RENDER_UNIT_TEXTURE 0
#define RENDER_UNIT_HEIGHT_MAP 1
#define RENDER_UNIT_ENVIRONMENT 2
#define RENDER_UNIT_SHADOW_MAP 3
