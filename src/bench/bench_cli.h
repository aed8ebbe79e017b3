#pragma once
// `tileshade bench`: registers the subcommand and its options; run() executes the parsed sweep.
#include <functional>

#include <CLI/CLI.hpp>

namespace ts {

struct CliCommand {
  CLI::App* command = nullptr;
  std::function<void()> run;
};

CliCommand addBenchCommand(CLI::App& app);

}  // namespace ts
