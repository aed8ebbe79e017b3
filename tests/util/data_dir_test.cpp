// Where an installed or a build-folder binary finds kernels/ and shaders/ (util/data_dir.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "util/data_dir.h"

namespace fs = std::filesystem;

namespace {

struct ScratchTree {
  fs::path root;
  ScratchTree() {
    root =
        fs::temp_directory_path() /
        ("tileshade_data_dir_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root);
    fs::create_directories(root);
  }
  ~ScratchTree() { fs::remove_all(root); }
};

void touch(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "";
}

}  // namespace

TEST(DataDir, OverrideWins) {
  ScratchTree t;
  fs::create_directories(t.root / "prefix/share/tileshade/kernels");
  EXPECT_EQ(
      ts::resolveDataDir("/elsewhere", t.root / "prefix/bin/tileshade", "kernels", "/src/kernels"),
      "/elsewhere");
}

TEST(DataDir, InstallTreeBesideTheExecutable) {
  ScratchTree t;
  fs::create_directories(t.root / "prefix/share/tileshade/kernels");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "prefix/bin/tileshade", "kernels", t.root.string()),
            (t.root / "prefix/share/tileshade/kernels").string());
}

TEST(DataDir, SourceTreeOnlyFromABuildFolder) {
  ScratchTree t;
  fs::create_directories(t.root / "src/kernels");
  const std::string source = (t.root / "src/kernels").string();
  // A copied binary with no install tree must not reach back into a source tree.
  touch(t.root / "copy/bin/tileshade");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "copy/bin/tileshade", "kernels", source),
            (t.root / "copy/share/tileshade/kernels").string());
  // From a build folder (or below it, as the fuzzers are) the source tree is used.
  touch(t.root / "build/CMakeCache.txt");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "build/tileshade", "kernels", source), source);
  EXPECT_EQ(ts::resolveDataDir("", t.root / "build/tests/fuzz/gltf_fuzzer", "kernels", source),
            source);
}

TEST(DataDir, InstallTreeWinsInsideABuildFolder) {
  ScratchTree t;
  touch(t.root / "build/CMakeCache.txt");
  fs::create_directories(t.root / "build/stage/share/tileshade/shaders");
  fs::create_directories(t.root / "src/shaders");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "build/stage/bin/tileshade", "shaders",
                               (t.root / "src/shaders").string()),
            (t.root / "build/stage/share/tileshade/shaders").string());
}

TEST(DataDir, InstallTreeOfTheLibrary) {
  // libtileshade.so in <prefix>/lib, as the Python module in <prefix>/lib/python3/dist-packages
  // loads it (its RPATH): the kernels are the library's install tree's, wherever python3 is.
  ScratchTree t;
  fs::create_directories(t.root / "prefix/share/tileshade/kernels");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "prefix/lib/libtileshade.so.0.1", "kernels", "/src"),
            (t.root / "prefix/share/tileshade/kernels").string());
  // The library of a build folder (the module in place, build/python/) reads the source tree.
  touch(t.root / "build/CMakeCache.txt");
  fs::create_directories(t.root / "src/kernels");
  EXPECT_EQ(ts::resolveDataDir("", t.root / "build/libtileshade.so.0.1", "kernels",
                               (t.root / "src/kernels").string()),
            (t.root / "src/kernels").string());
}

TEST(DataDir, UnknownExecutableKeepsTheSourceTree) {
  // Never a path relative to the working directory.
  EXPECT_EQ(ts::resolveDataDir("", fs::path(), "kernels", "/src/kernels"), "/src/kernels");
}

TEST(DataDir, ThisTestBinaryFindsTheSourceKernels) {
  const std::string dir =
      ts::dataDir("TILESHADE_NO_SUCH_VARIABLE", "kernels", TILESHADE_SOURCE_DIR "/kernels");
  EXPECT_TRUE(fs::exists(fs::path(dir) / "shading.h")) << dir;
}
