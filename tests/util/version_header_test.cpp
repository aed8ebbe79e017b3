// The version CMake's project() sets, as tileshade/version.h spells it (`tileshade --version`
// prints it: tests/cli/version_test.cpp).
#include <gtest/gtest.h>

#include <string>

#include "tileshade/version.h"

TEST(Version, HeaderMatchesItsParts) {
  const std::string parts = std::to_string(TILESHADE_VERSION_MAJOR) + "." +
                            std::to_string(TILESHADE_VERSION_MINOR) + "." +
                            std::to_string(TILESHADE_VERSION_PATCH);
  EXPECT_EQ(parts, TILESHADE_VERSION);
}
