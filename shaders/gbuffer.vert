#version 330 core
// The OpenGL rasterizer's vertex stage (src/raster/gl_rasterizer.cpp). Mirrors the software
// rasterizer's vertex transform (src/raster/rasterizer.cpp, transformVertices): view-space
// position from the float view matrix, view-space unit normal from the float normal matrix.

layout(location = 0) in vec3 a_position;  // world space (ts::Vertex)
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
#if TS_NORMAL_MAPS
layout(location = 3) in vec4 a_tangent;  // Scene::tangents: world xyz, w the bitangent's sign
uniform mat3 u_viewRotation;             // mat3(viewFromWorld)
out vec4 v_tangent;
#endif

uniform mat4 u_viewFromWorld;
uniform mat3 u_normalMatrix;  // transpose(inverse(mat3(viewFromWorld)))
uniform mat4 u_clipFromView;  // see clipFromView() in gl_rasterizer.cpp

out vec3 v_viewPosition;
out vec3 v_normal;
out vec2 v_uv;

void main() {
  vec4 p = u_viewFromWorld * vec4(a_position, 1.0);
  vec3 n = u_normalMatrix * a_normal;
  float len2 = dot(n, n);
  v_normal = len2 > 0.0 ? n / sqrt(len2) : vec3(0.0);
  v_viewPosition = p.xyz;
  v_uv = a_uv;
#if TS_NORMAL_MAPS
  v_tangent = vec4(u_viewRotation * a_tangent.xyz, a_tangent.w);
#endif
  gl_Position = u_clipFromView * p;
}
