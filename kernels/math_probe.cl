/*
 * math_probe: runs the kernels' own arithmetic helpers (kernels/gbuffer.h) on inputs the host
 * gives, so that a test holds each to its documented error on the device that shades
 * (tests/shading/math_probe_test.cpp). No technique uses this program.
 */
#include "gbuffer.h"

#if TS_LANES > 1
#define PROBE_VLOAD_(n) vload##n
#define PROBE_VLOAD(n) PROBE_VLOAD_(n)
#define PROBE_VSTORE_(n) vstore##n
#define PROBE_VSTORE(n) PROBE_VSTORE_(n)
#define PROBE_LOAD(p, i) PROBE_VLOAD(TS_LANES)(0, (p) + (i))
#define PROBE_STORE(v, p, i) PROBE_VSTORE(TS_LANES)((v), 0, (p) + (i))
#else
#define PROBE_LOAD(p, i) ((p)[i])
#define PROBE_STORE(v, p, i) ((p)[i] = (v))
#endif

/* out[i] = TS_POW(x[i], s[i]), the specular power as every shading kernel computes it, TS_LANES
 * values per work-item (the host passes a multiple of TS_LANES values). */
__kernel void specular_power(__global const float *x, __global const float *s,
                             __global float *out) {
  int i = (int)get_global_id(0) * TS_LANES;
  PROBE_STORE(TS_POW(PROBE_LOAD(x, i), PROBE_LOAD(s, i)), out, i);
}
