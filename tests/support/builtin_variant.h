#pragma once
// A built-in scene with a light set and a variant (SceneOptions), loaded anew each call.
#include <string>

#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace ts::test {

inline Scene builtin(const std::string& name, const std::string& lights,
                     const std::string& variant) {
  SceneOptions o;
  o.lightSet = lights;
  o.variant = variant;
  return loadScene("builtin:" + name, o);
}

}  // namespace ts::test
