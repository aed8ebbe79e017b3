#pragma once
// A registered subcommand (`bench`, `check`): main() parses the command line, then calls run()
// of the one that was given. Shared command-line plumbing, so check need not include bench.
#include <functional>

#include <CLI/CLI.hpp>

namespace ts {

struct CliCommand {
  CLI::App* command = nullptr;
  std::function<void()> run;
};

}  // namespace ts
