#version 430 core
// One triangle that covers the viewport (vertices from gl_VertexID, no buffers): the full-screen
// passes, e.g. shaders/shade_gbuffer.frag.
void main() {
  vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
  gl_Position = vec4(corner, 0.0, 1.0);
}
