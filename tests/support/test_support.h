#pragma once
// Shared pieces of the test suites: one OpenCL context per process (PoCL unless
// $TILESHADE_DEVICE says otherwise), where to find third-party scenes, and the tileshade binary.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cl/cl_context.h"

namespace ts::test {

// One context per process, never destroyed: an OpenCL runtime may tear down its own state in exit
// handlers that run before a static object's destructor, and releasing the context after them
// corrupted the heap at exit under Oclgrind (issue #12). The operating system reclaims it; it
// stays reachable, so leak checkers do not report it. Process-wide caches of OpenCL objects
// (cachedTechnique) are held the same way.
inline ClContext& context() {
  static ClContext* cl = new ClContext(std::getenv("TILESHADE_DEVICE") ? "" : "cpu");
  return *cl;
}

inline std::string sourceDir() {
  if (const char* env = std::getenv("TILESHADE_SOURCE_DIR"); env && *env) return env;
  return TILESHADE_SOURCE_DIR;
}

// An empty folder for one test's files: TMP/tileshade_<area>_<name>_<pid> (CTest runs tests in
// parallel processes, so the pid keeps two runs of one name apart).
inline std::filesystem::path freshDir(const std::string& area, const std::string& name) {
  namespace fs = std::filesystem;
  fs::path p = fs::temp_directory_path() /
               ("tileshade_" + area + "_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// ../shared/scenes beside the checkout (present in CI and on developer machines, absent for a
// new user): returns "" when the file is missing.
inline std::string sharedScene(const std::string& relative) {
  std::filesystem::path p =
      std::filesystem::path(sourceDir()) / ".." / "shared" / "scenes" / relative;
  return std::filesystem::exists(p) ? p.lexically_normal().string() : std::string();
}

// The command line: runs the tileshade binary (built beside the tests) with `args`.
struct CliRun {
  int status;          // as from pclose(); 0 = success
  std::string output;  // stderr, and stdout unless only stderr was asked for
  int exitCode() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
};

enum class Streams { Both, StderrOnly };

inline CliRun runTileshade(const std::string& args, Streams streams = Streams::Both) {
#ifdef TILESHADE_BINARY
  std::string cmd = std::string(TILESHADE_BINARY) + " " + args +
                    (streams == Streams::Both ? " 2>&1" : " 2>&1 >/dev/null");
#else
  (void)args;  // a test binary without the tileshade binary: every run fails
  (void)streams;
  std::string cmd = "false";
#endif
  CliRun r{0, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (fgets(buf, sizeof buf, p)) r.output += buf;
  r.status = pclose(p);
  return r;
}

}  // namespace ts::test
