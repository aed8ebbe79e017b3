// shade_gbuffer: an engine's side of tileshade's API in one file. It makes a small G-buffer in
// memory (a floor and a sphere, as an engine's geometry pass would), lights it, shades it with two
// techniques and checks each against tileshade's double-precision reference.
//   shade_gbuffer [DEVICE]     e.g. "cpu"; exit status 0 when both images match the reference
#include <cmath>
#include <cstdio>
#include <vector>

#include "tileshade/tileshade.h"

namespace {

constexpr int kWidth = 96, kHeight = 54;

struct Planes {
  std::vector<float> depth;
  std::vector<float> normal, diffuse, specular, emissive;  // 4 floats per pixel ("fp32")
};

// Ray-casts the scene in view space with the kernels' pixel convention (docs/api.md): the ray
// through pixel (x, y)'s centre, depth = -z of the nearest hit.
Planes rasterize(const ts::Camera& camera) {
  Planes p;
  const size_t n = size_t(kWidth) * kHeight;
  p.depth.assign(n, 0.0f);
  p.normal.assign(4 * n, 0.0f);
  p.diffuse.assign(4 * n, 0.0f);
  p.specular.assign(4 * n, 0.0f);
  p.emissive.assign(4 * n, 0.0f);
  const float cx = 0.0f, cy = 0.0f, cz = -6.0f, radius = 1.5f;  // sphere
  const float floorY = -1.5f;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const float dx = (2.0f * (x + 0.5f) / kWidth - 1.0f) * camera.tanHalfFovX;
      const float dy = (1.0f - 2.0f * (y + 0.5f) / kHeight) * camera.tanHalfFovY;
      const float dz = -1.0f;  // ray (dx, dy, -1): the hit's depth is its t
      float t = 0.0f, nx = 0.0f, ny = 1.0f, nz = 0.0f, r = 0.8f, g = 0.8f, b = 0.8f;
      // Sphere: |t d - c|^2 = radius^2.
      const float a = dx * dx + dy * dy + dz * dz, h = dx * cx + dy * cy + dz * cz;
      const float disc = h * h - a * (cx * cx + cy * cy + cz * cz - radius * radius);
      if (disc >= 0.0f) {
        t = (h - std::sqrt(disc)) / a;
        nx = (t * dx - cx) / radius;
        ny = (t * dy - cy) / radius;
        nz = (t * dz - cz) / radius;
        r = 0.9f, g = 0.3f, b = 0.2f;
      } else if (dy < 0.0f) {
        t = floorY / dy;  // the floor plane y = floorY
        if (t > 40.0f) t = 0.0f;
      }
      if (t <= camera.znear) continue;  // background
      const size_t i = size_t(y) * kWidth + x;
      p.depth[i] = t;
      const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
      float* normal = &p.normal[4 * i];
      normal[0] = nx / len, normal[1] = ny / len, normal[2] = nz / len;
      float* kd = &p.diffuse[4 * i];
      kd[0] = r, kd[1] = g, kd[2] = b, kd[3] = 1.0f;
      float* ks = &p.specular[4 * i];
      ks[0] = ks[1] = ks[2] = 0.3f, ks[3] = 32.0f;  // Blinn-Phong: ks rgb, shininess
    }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    ts::Device device(argc > 1 ? argv[1] : "");
    std::printf("tileshade %s on %s\n", TILESHADE_VERSION, device.name().c_str());
    const ts::Camera camera = ts::Camera::perspective(kWidth, kHeight, 1.0f, 0.1f, 100.0f);
    const Planes p = rasterize(camera);

    ts::HostGBuffer planes;
    planes.width = kWidth;
    planes.height = kHeight;
    planes.layout = "fp32";
    planes.depth = p.depth.data();
    planes.normal = p.normal.data();
    planes.diffuse = p.diffuse.data();
    planes.specular = p.specular.data();
    planes.emissive = p.emissive.data();

    ts::Lights lights;  // view space (camera.viewFromWorld is the identity)
    for (int k = 0; k < 16; ++k) {
      const float x = -6.0f + 0.8f * float(k), z = -3.0f - 0.5f * float(k % 5);
      lights.lights.push_back(ts::Light::point({x, -1.0f, z}, {0.6f, 0.5f, 0.4f}, 3.0f));
    }
    lights.lights.push_back(ts::Light::spot({0.0f, 3.0f, -6.0f}, {0.0f, -1.0f, 0.0f},
                                            {2.0f, 2.0f, 2.5f}, 8.0f, 0.2f, 0.5f));
    lights.lights.push_back(ts::Light::directional({0.0f, -0.8f, -0.6f}, {0.2f, 0.2f, 0.25f}));
    lights.ambient = {0.02f, 0.02f, 0.02f};
    ts::Frame frame = ts::Frame::fromHost(device, planes, camera, lights);
    std::printf("frame: %dx%d, %s, %s\n", frame.info().width, frame.info().height,
                frame.info().lightSummary.c_str(), frame.info().features.c_str());

    bool ok = true;
    for (const char* technique : {"tiled", "clustered"}) {
      ts::Settings settings;
      settings.technique = technique;
      ts::Renderer renderer(device, settings);
      ts::ShadeOptions options;
      options.check = true;
      const ts::ShadeResult r = renderer.shade(frame, options);
      const ts::CheckReport& check = *r.check;
      std::printf("%-10s %8.3f ms  max error/peak %.2e  missed %llu  (", technique, r.totalMs,
                  check.error.maxRelPeak, (unsigned long long)check.missed);
      for (size_t k = 0; k < r.kernels.size(); ++k)
        std::printf("%s%s=%.3f", k ? " " : "", r.kernels[k].name.c_str(), r.kernels[k].ms);
      std::printf(")\n");
      // tileshade's own accuracy bound for fp32 planes (docs/accuracy.md): 1e-4 of the peak.
      ok = ok && check.missed == 0 && check.error.maxRelPeak <= 1e-4 && r.nonfinitePixels == 0;
    }
    std::printf("%s\n", ok ? "ok" : "FAILED: an image is off the reference");
    return ok ? 0 : 1;
  } catch (const ts::Error& e) {
    std::fprintf(stderr, "shade_gbuffer: error: %s\n", e.what());
    return 2;
  }
}
