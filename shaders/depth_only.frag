#version 330 core
// The depth-only pre-pass of tiled-forward-prez (src/raster/gl_rasterizer.cpp, depthPrepass):
// the hardware depth buffer for the forward pass's EQUAL test, and the linear view depth -z_view
// (as the G-buffer's depth plane) for the OpenCL tile_depth_bounds kernel.
in vec3 v_viewPosition;
layout(location = 1) out float o_depth;
void main() { o_depth = -v_viewPosition.z; }
