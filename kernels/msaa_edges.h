/*
 * --msaa for tiled deferred shading (Lauritzen, "Deferred Rendering for Current and Future
 * Rendering Pipelines", SIGGRAPH 2010): the edge mask of a multisampled G-buffer. Host side in
 * src/techniques/multisampled_gbuffer.cpp; the per-sample shading of the edges is
 * shade_tiled_edge_samples (kernels/tiled.cl).
 *
 * The planes hold `samples` planes of width x height one after another (sample-major: sample k
 * of pixel i at k * width * height + i), in the frame's layout. A pixel is an edge when, in any
 * plane present, any sample's stored element differs from sample 0's in any bit (depth compared
 * as its 32 bits). The rule is exact rather than Lauritzen's thresholds on depth and normal: a
 * pixel that is no edge holds one stored surface in every sample, so sample 0's shade is every
 * sample's, bit for bit, and the resolved image equals shading every sample. It reads what
 * thresholds would (compares instead of dot products), and with the pixel-centre interpolation
 * of the G-buffer pass (docs/techniques.md "MSAA") samples of one triangle are bitwise equal, so
 * it flags only pixels a triangle boundary crosses (also inside one smooth surface, which
 * thresholds would let pass: counted in docs/techniques.md "MSAA").
 * plane_bytes: bytes per element of the normal, diffuse, specular and emissive planes (0 =
 * absent). edge: one byte per pixel, 1 = edge.
 */
#ifndef TS_MSAA_EDGES_H
#define TS_MSAA_EDGES_H

/* The bits in which elements a and b of a plane of `bytes` per element differ (OR-ed), in
 * 32-bit words where the element is whole words (all but metallic-roughness packed's roughness
 * byte). Without early exits, so that the loops stay straight for PoCL's vectorising across
 * work-items: the byte-by-byte, early-exit first form took about 2x longer (bench/RESULTS.md). */
static inline uint ts_element_diff(__global const uchar *plane, int bytes, size_t a, size_t b) {
  uint diff = 0u;
  if ((bytes & 3) == 0) {
    __global const uint *words = (__global const uint *)plane;
    size_t n = (size_t)(bytes >> 2);
    for (size_t j = 0; j < n; ++j) diff |= words[a * n + j] ^ words[b * n + j];
  } else {
    for (int j = 0; j < bytes; ++j)
      diff |= (uint)(plane[a * (size_t)bytes + (size_t)j] ^ plane[b * (size_t)bytes + (size_t)j]);
  }
  return diff;
}

__kernel void msaa_edge_mask(__global const uint *depth_bits, __global const uchar *normal,
                             __global const uchar *diffuse, __global const uchar *specular,
                             __global const uchar *emissive, int4 plane_bytes, int width,
                             int height, int samples, __global uchar *edge) {
  int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  size_t i = (size_t)y * (size_t)width + (size_t)x, plane = (size_t)width * (size_t)height;
  uint diff = 0u;
  for (int k = 1; k < samples; ++k) {
    size_t j = (size_t)k * plane + i;
    diff |= (depth_bits[j] ^ depth_bits[i]) | ts_element_diff(normal, plane_bytes.x, i, j) |
            ts_element_diff(diffuse, plane_bytes.y, i, j) |
            ts_element_diff(specular, plane_bytes.z, i, j) |
            ts_element_diff(emissive, plane_bytes.w, i, j);
  }
  edge[i] = (uchar)(diff != 0u);
}

/* Plane `p` (elements of `type`, `bytes` per pixel, 0 = absent) from sample offset `o` pixels on:
 * what ts_load_surface reads as sample o / (width * height)'s plane. */
#define TS_SAMPLE_PLANE(type, p, bytes, o)                                                      \
  ((__global const type *)((__global const uchar *)(p) + (o) * (size_t)(bytes)))

/* ts_load_surface at (x, y) of the sample whose planes start `o` pixels on (o = k * width *
 * height for sample k), in a kernel with TS_GBUFFER_PARAMS: what every --msaa edge kernel shades. */
#define TS_LOAD_SAMPLE_SURFACE(x, y, camera, ambient, o, plane_bytes, s)                         \
  ts_load_surface(x, y, camera, ambient, gb_depth + (o),                                        \
                  TS_SAMPLE_PLANE(ts_gb_normal, gb_normal, (plane_bytes).x, o),                 \
                  TS_SAMPLE_PLANE(ts_gb_diffuse, gb_diffuse, (plane_bytes).y, o),               \
                  TS_SAMPLE_PLANE(ts_gb_specular, gb_specular, (plane_bytes).z, o),             \
                  TS_SAMPLE_PLANE(ts_gb_emissive, gb_emissive, (plane_bytes).w, o), s)

#endif
