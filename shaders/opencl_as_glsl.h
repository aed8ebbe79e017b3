/*
 * The prelude that lets GLSL compile kernels/shading.h, the OpenCL C header every technique's
 * kernels and the double reference shade with, as it is: the common subset's types and the few
 * constructs GLSL spells differently (see the macros at the top of kernels/shading.h). Macros
 * only: no term of the shading model is written here.
 *
 * A shader includes this file, then "kernels/shading.h" (src/raster/gl_program.cpp reads that
 * from the OpenCL kernel folder, kernelDir(), so the GLSL build is the kernels' file itself).
 * Needs GLSL 4.20 or later: struct initializer lists, const locals with computed values.
 */
#ifndef TS_OPENCL_AS_GLSL_H
#define TS_OPENCL_AS_GLSL_H

#define static
#define inline
#define TS_REAL float
#define TS_REAL3 vec3
#define TS_REAL4 vec4
#define TS_MAKE3(x, y, z) vec3((x), (y), (z))
#define TS_MAKE4(x, y, z, w) vec4((x), (y), (z), (w))
#define TS_LIT(x) x /* an unsuffixed literal is a float in GLSL */
#define TS_RSQRT inversesqrt
#define TS_CAST(type, x) type(x)
#define TS_STRUCT_BEGIN(name) struct name
#define TS_STRUCT_END(name)
#define TS_IN(type, name) in type name
#define TS_OUT(type, name) out type name
#define TS_DEREF(p) (p)
#define TS_ADDR(x) (x)

#endif
