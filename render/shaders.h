// The renderer's GLSL programs (shaders.cpp): surfaces and instanced primitives lit (headlight and
// key light, rim on transparent surfaces), lines and the 2D overlay flat. Internal to render/.
// Needs a current GL context with the table of gl_api.h loaded.
#pragma once

namespace ps::render::shaders {

extern const char* const kSurfaceVs;   // scene surfaces: position, normal, displacement scalar
extern const char* const kInstanceVs;  // instanced spheres, cylinders, cones (model matrix, colour)
extern const char* const kLitFs;       // their lighting
extern const char* const kLineVs;      // coloured line segments
extern const char* const kFlatFs;      // unlit colour (lines, overlay)
extern const char* const kOverlayVs;   // 2D overlay in pixels (origin top-left)

// Compiles vs and fs as "#version 330 core" (the vertex stage with the colour map cmap()) and
// links them; throws RenderError with the driver's log.
unsigned link(const char* vs, const char* fs);

}  // namespace ps::render::shaders
