#pragma once
// Values of numeric command-line options, checked in one place for `render`, `scene export` and
// `bench` (whose sweep values and --config fields arrive as text): a value that makes no sense
// (NaN, inf, a negative exposure, zero slices, a billion lights) is one line
// "OPTION: expected ..., got 'VALUE'" (ts::Error) before any work starts.
#include <string>
#include <utility>
#include <vector>

namespace ts {

// Limits shared by `render` and `bench`.
constexpr long long kMaxLightCount = 1 << 24;  // --light-count (memory: ~100 bytes per light)
constexpr int kMaxImageSide = 16384;           // --width, --height, --resolution
constexpr int kMaxTileSide = 256;              // --tile (the techniques' work-group bound)
// --slices, and what clustered accepts: its cluster_depth_bounds keeps 12 bytes per slice in local
// memory, 14 KB at 1024 slices, within the 32 KB every OpenCL 1.2 device has (4096 needed 50 KB).
constexpr int kMaxClusterSlices = 1024;

enum class NumberRule {
  AtLeastZero,  // finite, >= 0 (0 usually means "keep")
  AboveZero,    // finite, > 0
};

// A number already parsed (render's options come typed from CLI11): throws unless it is finite,
// follows `rule` and is at most `max`. Returns it as float.
float checkNumber(const std::string& option, double value, NumberRule rule,
                  double max = 3.4028234663852886e38);
// An integer already parsed: throws unless lo <= value <= hi.
long long checkInteger(const std::string& option, long long value, long long lo, long long hi);

// The same from text (the whole text must be the number, surrounding spaces allowed).
float parseNumber(const std::string& option, const std::string& text, NumberRule rule,
                  double max = 3.4028234663852886e38);
long long parseInteger(const std::string& option, const std::string& text, long long lo,
                       long long hi);
// What parseNumber checks, without the option: "" when `text` is such a number, else
// "expected ..., got 'TEXT'" (for CLI11 validators, which run on the text as typed).
std::string numberTextProblem(const std::string& text, NumberRule rule,
                              double max = 3.4028234663852886e38);

// "16" | "32x16", sides 1..kMaxTileSide; option --tile.
std::pair<int, int> parseTileSize(const std::string& text);
// "1280x720", sides 1..kMaxImageSide; option --resolution.
std::pair<int, int> parseResolution(const std::string& text);

// Throws ts::Error "OPTION: WHAT, got 'VALUE'", the one form of every bad option value.
[[noreturn]] void badOptionValue(const std::string& option, const std::string& value,
                                 const std::string& what);

// Leading and trailing white space removed.
std::string trimmed(const std::string& s);

// Splits "a,b , c" into trimmed non-empty items.
std::vector<std::string> splitList(const std::string& s, char sep = ',');

}  // namespace ts
