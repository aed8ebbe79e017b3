#pragma once
// Random test inputs drawn in an order the compiler does not choose.
#include <array>
#include <cstddef>
#include <utility>

namespace ts::test {

// N draws of `draw`, one per statement, the last element drawn first. C++ leaves the order of a
// call's arguments unspecified (g++ on x86-64 evaluates them right to left, clang left to right),
// so `glm::vec3(u(rng), u(rng), u(rng))` was another vector under clang; last-first keeps the
// values g++ drew, with which the tests' cases and bounds were chosen.
template <size_t N, typename Draw>
auto drawnLastFirst(Draw&& draw) {
  std::array<decltype(draw()), N> values{};
  for (size_t i = N; i-- > 0;) values[i] = draw();
  return values;
}

}  // namespace ts::test
