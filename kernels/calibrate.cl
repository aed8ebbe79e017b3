/*
 * Calibration kernels of `tileshade bench` (host side: src/bench/calibrate.cpp). They measure, on
 * the device and in the run being benchmarked, the two rates the device-limit estimate uses:
 *   copy_float4   out[i] = in[i] over a buffer much larger than any cache: copy bandwidth
 *                 = (bytes read + bytes written) / time
 *   fma_chain     CAL_CHAINS independent chains of multiply-adds per work-item, each on a vector
 *                 of CAL_WIDTH floats (the device's native float width, so a CPU's SIMD units and a
 *                 GPU's scalar lanes are both filled): peak arithmetic rate, counting a
 *                 multiply-add as 2 floating-point operations
 */
#ifndef CAL_WIDTH
#define CAL_WIDTH 1
#endif
#ifndef CAL_CHAINS
#define CAL_CHAINS 8
#endif

#if CAL_WIDTH == 1
typedef float calvec;
#define CAL_SPLAT(x) ((float)(x))
#define CAL_SUM(v) (v)
#elif CAL_WIDTH == 2
typedef float2 calvec;
#define CAL_SPLAT(x) ((float2)(x))
#define CAL_SUM(v) ((v).s0 + (v).s1)
#elif CAL_WIDTH == 4
typedef float4 calvec;
#define CAL_SPLAT(x) ((float4)(x))
#define CAL_SUM(v) ((v).s0 + (v).s1 + (v).s2 + (v).s3)
#elif CAL_WIDTH == 8
typedef float8 calvec;
#define CAL_SPLAT(x) ((float8)(x))
#define CAL_SUM(v) ((v).s0 + (v).s1 + (v).s2 + (v).s3 + (v).s4 + (v).s5 + (v).s6 + (v).s7)
#else
typedef float16 calvec;
#define CAL_SPLAT(x) ((float16)(x))
#define CAL_SUM(v) ((v).s0 + (v).s1 + (v).s2 + (v).s3 + (v).s4 + (v).s5 + (v).s6 + (v).s7 + \
                    (v).s8 + (v).s9 + (v).sa + (v).sb + (v).sc + (v).sd + (v).se + (v).sf)
#endif

__kernel void copy_float4(__global const float4 *in, __global float4 *out) {
  size_t i = get_global_id(0);
  out[i] = in[i];
}

/* Every chain is x = x*m + c with m slightly below 1, so values stay finite for any length; the
 * sum is written out so nothing can be optimised away. `iterations` is a runtime argument, so the
 * compiler cannot fold the loop. */
__kernel void fma_chain(__global float *out, int iterations, float m, float c) {
  size_t gid = get_global_id(0);
  calvec seed = CAL_SPLAT((float)(gid & 1023) * 1e-4f);
  calvec vm = CAL_SPLAT(m), vc = CAL_SPLAT(c);
  calvec x0 = seed + CAL_SPLAT(0.0f), x1 = seed + CAL_SPLAT(0.1f);
  calvec x2 = seed + CAL_SPLAT(0.2f), x3 = seed + CAL_SPLAT(0.3f);
#if CAL_CHAINS > 4
  calvec x4 = seed + CAL_SPLAT(0.4f), x5 = seed + CAL_SPLAT(0.5f);
  calvec x6 = seed + CAL_SPLAT(0.6f), x7 = seed + CAL_SPLAT(0.7f);
#endif
  for (int i = 0; i < iterations; ++i) {
    x0 = mad(x0, vm, vc);
    x1 = mad(x1, vm, vc);
    x2 = mad(x2, vm, vc);
    x3 = mad(x3, vm, vc);
#if CAL_CHAINS > 4
    x4 = mad(x4, vm, vc);
    x5 = mad(x5, vm, vc);
    x6 = mad(x6, vm, vc);
    x7 = mad(x7, vm, vc);
#endif
  }
  calvec s = x0 + x1 + x2 + x3;
#if CAL_CHAINS > 4
  s += x4 + x5 + x6 + x7;
#endif
  out[gid] = CAL_SUM(s);
}
