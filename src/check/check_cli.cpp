#include "check/check_cli.h"

#include <iostream>
#include <memory>

#include "check/check_run.h"
#include "check/hard_cases.h"
#include "techniques/technique.h"
#include "util/error.h"

namespace ts {

CliCommand addCheckCommand(CLI::App& app) {
  struct Parsed {
    CheckOptions options;
    std::vector<std::string> formats{"all"};
    bool list = false;
  };
  auto parsed = std::make_shared<Parsed>();
  CliCommand c;
  c.command = app.add_subcommand(
      "check",
      "hard-case suite: small scenes at the edges of the pipeline (lights behind or around the "
      "camera, extreme ranges and depth ratios, lights on surfaces and in their planes, scenes far "
      "from the origin, odd resolutions, 1e5 lights, fp16 and fp32 limits) through every "
      "technique, G-buffer layout and lanes 1 and 16, against the double reference; exit status "
      "1 if any run fails (docs/hard-cases.md)");
  c.command->add_option("--case", parsed->options.cases,
                        "hard case(s) to run (default: all; see --list)");
  c.command->add_option("--technique", parsed->options.techniques, "technique(s) (default: all)");
  c.command
      ->add_option("--gbuffer", parsed->formats,
                   "G-buffer layout(s): " + gbufferFormatNames().list() + ", all")
      ->capture_default_str();
  c.command->add_option("--lanes", parsed->options.lanes, "lanes widths (a case may add its own)")
      ->capture_default_str();
  c.command->add_option("--device", parsed->options.device,
                        "OpenCL device (see `devices`); default: first GPU, else CPU, or "
                        "$TILESHADE_DEVICE");
  c.command->add_flag("--list", parsed->list, "list the hard cases and exit");
  c.run = [parsed] {
    if (parsed->list) {
      for (const auto& hc : hardCases()) std::cout << hc.name << "  " << hc.description << "\n";
      return;
    }
    CheckOptions o = parsed->options;
    o.formats.clear();
    for (const auto& f : parsed->formats) {
      if (f == "all") {
        o.formats = {GBufferFormat::FP32, GBufferFormat::FP16, GBufferFormat::PACKED};
        break;
      }
      o.formats.push_back(gbufferFormatNames().parseOption("--gbuffer", f));
    }
    for (int lanes : o.lanes)
      if (lanes < 1) throw Error("--lanes takes widths 1, 2, 4, 8, 16");
    for (auto& t : o.techniques)
      if (t == "all") o.techniques.clear();
    std::vector<CheckRow> rows = runHardCases(o, std::cout);
    size_t failed = 0;
    for (const auto& r : rows) failed += !r.pass();
    if (failed)
      throw Error("check: " + std::to_string(failed) + " of " + std::to_string(rows.size()) +
                  " hard-case runs failed (FAIL rows above)");
    std::cout << "check: all " << rows.size() << " hard-case runs passed\n";
  };
  return c;
}

}  // namespace ts
