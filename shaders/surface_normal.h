/*
 * The shading normal of a rasterized fragment: ONE definition for the OpenGL G-buffer pass
 * (shaders/gbuffer.frag) and the forward passes (shaders/tiled_forward.frag), the rules of the
 * software rasterizer's resolve() (src/raster/rasterizer.cpp): the interpolated vertex normal,
 * renormalised; where it vanishes, the geometric normal turned towards the viewer (away from it
 * for a back face); flipped for the back of a double-sided material.
 * face_normal: cross(dFdx(P), dFdy(P)), taken by the caller outside any branch (derivatives are
 * undefined in non-uniform control flow).
 */
vec3 ts_surface_normal(vec3 interpolated, vec3 face_normal, vec3 view_position, bool double_sided) {
  vec3 n = interpolated;
  float len2 = dot(n, n);
  if (len2 > 1e-24) {
    n = n / sqrt(len2);
  } else {
    float gl2 = dot(face_normal, face_normal);
    n = gl2 > 0.0 ? face_normal / sqrt(gl2) : vec3(0.0, 0.0, 1.0);
    if (dot(n, view_position) > 0.0) n = -n;
    if (!gl_FrontFacing) n = -n;
  }
  if (double_sided && !gl_FrontFacing) n = -n;
  return n;
}
