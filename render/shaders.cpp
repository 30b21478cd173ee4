// The renderer's GLSL programs (OpenGL 3.3 core) and their compile and link.
#include "render/shaders.h"

#include <string>

#include "render/gl_api.h"
#include "render/render_error.h"

namespace ps::render::shaders {

using gl::api;

namespace {

constexpr const char* kColourMapGlsl = R"(
vec3 cmap(float t) {
  const vec3 c0 = vec3(0.267, 0.005, 0.329), c1 = vec3(0.229, 0.322, 0.546),
             c2 = vec3(0.128, 0.567, 0.551), c3 = vec3(0.369, 0.789, 0.383), c4 = vec3(0.993, 0.906, 0.144);
  t = clamp(t, 0.0, 1.0) * 4.0;
  if (t < 1.0) return mix(c0, c1, t);
  if (t < 2.0) return mix(c1, c2, t - 1.0);
  if (t < 3.0) return mix(c2, c3, t - 2.0);
  return mix(c3, c4, t - 3.0);
}
)";

unsigned compile(GLenum type, const std::string& src) {
  const unsigned s = api.CreateShader(type);
  const std::string full = std::string("#version 330 core\n") + (type == GL_VERTEX_SHADER ? kColourMapGlsl : "") + src;
  const char* p = full.c_str();
  api.ShaderSource(s, 1, &p, nullptr);
  api.CompileShader(s);
  int ok = 0;
  api.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    api.GetShaderInfoLog(s, sizeof log, nullptr, log);
    throw RenderError(std::string("shader compile failed: ") + log);
  }
  return s;
}

}  // namespace

const char* const kSurfaceVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aScalar;
uniform mat4 uViewProj;
uniform vec4 uColour;
uniform int uUseScalar;
uniform float uScalarMax;
out vec3 vPos; out vec3 vNormal; out vec4 vColour;
void main() {
  vPos = aPos; vNormal = aNormal;
  vColour = uUseScalar == 1 ? vec4(cmap(aScalar / uScalarMax), uColour.a) : uColour;
  gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

const char* const kInstanceVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 3) in vec4 iM0;
layout(location = 4) in vec4 iM1;
layout(location = 5) in vec4 iM2;
layout(location = 6) in vec4 iM3;
layout(location = 7) in vec4 iColour;
uniform mat4 uViewProj;
out vec3 vPos; out vec3 vNormal; out vec4 vColour;
void main() {
  mat4 m = mat4(iM0, iM1, iM2, iM3);
  vec4 w = m * vec4(aPos, 1.0);
  vPos = w.xyz;
  vNormal = transpose(inverse(mat3(m))) * aNormal;
  vColour = iColour;
  gl_Position = uViewProj * w;
}
)";

// Headlight plus a key light from above-anterior; two-sided; transparent surfaces get a rim
// (more opaque where seen edge-on) so an organ's outline reads through the fat.
const char* const kLitFs = R"(
in vec3 vPos; in vec3 vNormal; in vec4 vColour;
uniform vec3 uEye;
uniform float uRim;
out vec4 oColour;
void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uEye - vPos);
  vec3 key = normalize(vec3(0.35, 0.45, 0.82));
  float nv = max(dot(n, v), 0.0);
  float diff = 0.55 * nv + 0.35 * max(dot(n, key), 0.0);
  // powers by multiplication: pow() costs a software rasteriser exp2(log2()) per pixel
  float s = max(dot(n, normalize(key + v)), 0.0);
  s *= s; s *= s; s *= s; s *= s; s *= s;  // s^32
  float spec = 0.22 * s;
  vec3 rgb = vColour.rgb * (0.28 + diff) + vec3(spec);
  float a = vColour.a;
  float e = 1.0 - nv;
  if (a < 0.999) a = clamp(a + uRim * (1.0 - a) * e * e * e, 0.0, 1.0);
  oColour = vec4(rgb, a);
}
)";

const char* const kLineVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProj;
out vec4 vColour;
void main() { vColour = aColour; gl_Position = uViewProj * vec4(aPos, 1.0); }
)";
const char* const kFlatFs = R"(
in vec4 vColour;
out vec4 oColour;
void main() { oColour = vColour; }
)";
const char* const kOverlayVs = R"(
layout(location = 0) in vec2 aPos;
layout(location = 1) in vec4 aColour;
uniform vec2 uScreen;
out vec4 vColour;
void main() {
  vColour = aColour;
  gl_Position = vec4(2.0 * aPos.x / uScreen.x - 1.0, 1.0 - 2.0 * aPos.y / uScreen.y, 0.0, 1.0);
}
)";

unsigned link(const char* vs, const char* fs) {
  const unsigned v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  const unsigned p = api.CreateProgram();
  api.AttachShader(p, v);
  api.AttachShader(p, f);
  api.LinkProgram(p);
  api.DeleteShader(v);
  api.DeleteShader(f);
  int ok = 0;
  api.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    api.GetProgramInfoLog(p, sizeof log, nullptr, log);
    throw RenderError(std::string("shader link failed: ") + log);
  }
  return p;
}

}  // namespace ps::render::shaders
