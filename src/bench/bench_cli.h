#pragma once
// `tileshade bench`: registers the subcommand and its options; run() executes the parsed sweep.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "bench/bench_run.h"
#include "util/cli_command.h"

namespace ts {

CliCommand addBenchCommand(CLI::App& app);

// Applies a --config document (JSON text; `source` names it in errors) to `o`: dimension names
// as keys (lists or single values), frames, warmup, repeat, error, error_frames, calib_mib,
// description. A field for which givenOnCommandLine(field) is true keeps the command line's value.
// Every value is type- and range-checked here or by expandSweep(); ts::Error with one line.
void applyBenchConfig(const std::string& text, const std::string& source, BenchOptions& o,
                      const std::function<bool(const std::string& field)>& givenOnCommandLine);

}  // namespace ts
