// ts::runBench of tileshade.h: `tileshade bench --config` from the caller's JSON text, its
// bench.csv read back as rows.
#include "api/api_internal.h"
#include "bench/bench_cli.h"
#include "bench/bench_columns.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "util/error.h"
#include "util/file_read.h"

namespace ts {

std::vector<std::map<std::string, std::string>> runBench(const BenchRequest& request) {
  if (request.outDir.empty()) throw Error("runBench: outDir is empty (where bench.csv goes)");
  if (!request.configJson.empty() && !request.configPath.empty())
    throw Error("runBench: give configJson or configPath, not both");
  // A file is read as `bench --config` reads it (a directory or a missing file: one line naming
  // it); errors in the document name the file, or say it was the configJson text.
  const bool fromFile = !request.configPath.empty();
  const std::string text =
      fromFile ? readTextFile(request.configPath, "bench config") : request.configJson;
  BenchOptions o;
  // No command line: every field of the document applies.
  applyBenchConfig(text, fromFile ? request.configPath : "(runBench's configJson)", o,
                   [](const std::string&) { return false; });
  o.outDir = request.outDir;
  o.overwrite = true;
  o.calibrate = request.calibrate;
  o.progress = !request.quiet;
  o.printTable = false;  // a library prints nothing on stdout
  o.command = "ts::runBench";
  const BenchRunResult r = runBench(o);
  if (!r.failures.empty())
    throw Error(std::to_string(r.failures.size()) +
                " configuration(s) failed, the first: " + r.failures.front());
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  const std::string csv = request.outDir + "/bench.csv";
  if (!readCsv(csv, header, rows)) throw Error("runBench: the bench wrote no " + csv);
  if (header != benchCsvColumns())
    throw Error(csv + " does not have bench.csv's columns (another version's file?)");
  return rows;
}

}  // namespace ts
