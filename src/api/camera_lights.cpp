// The value types of tileshade.h: Camera::perspective and the Light constructors.
#include "api/api_internal.h"
#include "gbuffer/gbuffer.h"

namespace ts {

Camera Camera::perspective(int width, int height, float yfov, float znear, float zfar) {
  SceneCamera scene;
  scene.yfov = yfov;
  scene.znear = znear;
  scene.zfar = zfar;
  // The render command's own intrinsics (and its checks: yfov in (0, pi), 0 < znear < zfar).
  const CameraIntrinsics in = CameraIntrinsics::from(scene, width, height);
  Camera c;
  c.width = in.width;
  c.height = in.height;
  c.tanHalfFovX = in.tanHalfFovX;
  c.tanHalfFovY = in.tanHalfFovY;
  c.znear = in.znear;
  c.zfar = in.zfar;
  return c;
}

Light Light::point(Float3 position, Float3 color, float range) {
  Light l;
  l.type = LightType::Point;
  l.position = position;
  l.color = color;
  l.range = range;
  return l;
}

Light Light::spot(Float3 position, Float3 direction, Float3 color, float range,
                  float innerConeAngle, float outerConeAngle) {
  Light l = point(position, color, range);
  l.type = LightType::Spot;
  l.direction = direction;
  l.innerConeAngle = innerConeAngle;
  l.outerConeAngle = outerConeAngle;
  return l;
}

Light Light::directional(Float3 direction, Float3 color) {
  Light l;
  l.type = LightType::Directional;
  l.direction = direction;
  l.color = color;
  return l;
}

}  // namespace ts
