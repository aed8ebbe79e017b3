// libFuzzer target: a `tileshade bench --config` file's text through the config parser, the
// sweep expansion (every value parsed and validated) and the frame specs, as `bench` does before
// it runs anything. Any outcome but success or a ts::Error is a bug.
#include <cstdint>
#include <string>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ts::BenchOptions options;
  try {
    ts::applyBenchConfig(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json",
                         options, [](const std::string&) { return false; });
    ts::expandSweep(options.sweep);
    options.frames.validate();
    ts::selectErrorFrames(options.errorFrames, {0, 10, 20});
  } catch (const ts::Error&) {
    // a clear one-line error: the expected outcome for a bad config
  }
  return 0;
}
