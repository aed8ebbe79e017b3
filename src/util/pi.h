#pragma once
// pi, defined once. Float code (the built-in scenes, meshes, the glTF loader's default cameras)
// uses kPi, pi rounded to a float (3.14159274), so its arithmetic stays in float.
namespace ts {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kPi = float(kPiDouble);
constexpr double kHalfPi = kPiDouble / 2.0;  // exact: 1.5707963267948966

}  // namespace ts
