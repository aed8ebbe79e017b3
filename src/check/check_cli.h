#pragma once
// `tileshade check`: registers the subcommand; run() prints the hard-case table and throws
// ts::Error (exit status 1) when any run fails.
#include <CLI/CLI.hpp>

#include "util/cli_command.h"

namespace ts {

CliCommand addCheckCommand(CLI::App& app);

}  // namespace ts
