// `--variant glass`: panes and volumes of glass (alphaMode BLEND, opacity < 1, double-sided) in
// the built-in scenes, placed where their default cameras (frame 0) look, so that a frame shows
// glass over glass and glass over lit geometry (scenes/README.md). Drawn by the forward
// techniques with `--blend blend`; refused by default as any BLEND material is.
#include "scene/builtin_scenes.h"
#include "scene/mesh_builder.h"
#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

uint32_t glassMaterial(MeshBuilder& mb, const char* name, glm::vec3 tint, float opacity) {
  Material m;
  m.name = name;
  m.diffuse = 0.5f * tint;
  // Below 0.5 so that the metallic-roughness mapping reads it as a dielectric.
  m.specular = glm::vec3(0.45f);
  m.shininess = 96.0f;
  m.alphaMode = AlphaMode::Blend;
  m.opacity = opacity;
  m.doubleSided = true;  // both faces of a pane are seen, and lit from their side
  return mb.addMaterial(m);
}

// A vertical pane in the plane z = z, facing +z.
void paneAcrossZ(MeshBuilder& mb, float z, float x0, float x1, float y0, float y1, uint32_t m) {
  mb.quad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, m);
}

// A vertical pane in the plane x = x, facing +x.
void paneAcrossX(MeshBuilder& mb, float x, float z0, float z1, float y0, float y1, uint32_t m) {
  mb.quad({x, y0, z1}, {x, y0, z0}, {x, y1, z0}, {x, y1, z1}, m);
}

// Frame 0 stands at (0, 1.7, 140) looking down -Z: two tinted panes across the road in front of
// it, overlapping on screen; shop-window panes along both kerbs every 20 m; a glass shelter.
void addStreetGlass(MeshBuilder& mb) {
  const uint32_t green = glassMaterial(mb, "glass_green", {0.55f, 0.9f, 0.75f}, 0.4f);
  const uint32_t amber = glassMaterial(mb, "glass_amber", {1.0f, 0.7f, 0.3f}, 0.55f);
  const uint32_t clear = glassMaterial(mb, "glass_clear", {0.85f, 0.9f, 1.0f}, 0.3f);
  paneAcrossZ(mb, 128.0f, -5.0f, 1.0f, 0.0f, 3.0f, green);
  paneAcrossZ(mb, 120.0f, -2.0f, 5.0f, 0.5f, 4.0f, amber);
  for (float z = 130.0f; z > -140.0f; z -= 20.0f) {
    paneAcrossX(mb, 11.3f, z - 6.0f, z, 0.2f, 2.7f, clear);
    paneAcrossX(mb, -11.3f, z - 6.0f, z, 0.2f, 2.7f, clear);
  }
  mb.box(glm::vec3(-9.5f, 0.0f, 106.0f), glm::vec3(-6.5f, 2.5f, 107.5f), clear, false);
}

// Frame 0 stands at (11, 1.7, 0) looking towards -X across the courtyard: two screens across it,
// overlapping on screen, and a glass vitrine beyond them.
void addAtriumGlass(MeshBuilder& mb) {
  const uint32_t blue = glassMaterial(mb, "glass_blue", {0.6f, 0.8f, 1.0f}, 0.35f);
  const uint32_t rose = glassMaterial(mb, "glass_rose", {1.0f, 0.6f, 0.7f}, 0.5f);
  const uint32_t clear = glassMaterial(mb, "glass_clear", {0.9f, 0.95f, 1.0f}, 0.3f);
  paneAcrossX(mb, 6.0f, -3.0f, 3.0f, 0.0f, 3.0f, blue);
  paneAcrossX(mb, 0.0f, -1.0f, 5.0f, 0.3f, 4.0f, rose);
  mb.box(glm::vec3(-7.0f, 0.0f, -1.5f), glm::vec3(-5.0f, 2.0f, 1.5f), clear, false);
}

}  // namespace

void addGlass(Scene& scene) {
  MeshBuilder mb(scene);
  if (scene.name == "street") addStreetGlass(mb);
  else if (scene.name == "atrium") addAtriumGlass(mb);
  else throw Error("variant glass: no glass is placed in scene '" + shortText(scene.name) + "'");
}

}  // namespace ts
