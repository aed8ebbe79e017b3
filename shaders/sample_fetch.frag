#version 430 core
// One sample of a multisampled target into a single-sample one (src/raster/gl_rasterizer.cpp,
// --msaa): glBlitFramebuffer resolves (averages) and cannot pick a sample, glGetTexImage cannot
// read a multisample texture, so a full-screen pass fetches sample u_sample of each pixel with
// texelFetch, bit for bit, and the single-sample target is read back as without MSAA. Float
// targets through u_float (output 0), integer ones through u_int (output 1).
uniform sampler2DMS u_float;
uniform isampler2DMS u_int;
uniform int u_sample;
uniform bool u_integer;
layout(location = 0) out vec4 o_float;
layout(location = 1) out ivec4 o_int;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  if (u_integer) o_int = texelFetch(u_int, pixel, u_sample);
  else o_float = texelFetch(u_float, pixel, u_sample);
}
