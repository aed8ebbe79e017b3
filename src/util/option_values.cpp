#include "util/option_values.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <sstream>

#include "util/error.h"
#include "util/short_text.h"

namespace ts {
namespace {

std::string numberText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string ruleText(NumberRule rule, double max) {
  std::string s = rule == NumberRule::AboveZero ? "a finite number > 0" : "a finite number >= 0";
  if (max < 3.4e38) s += " and <= " + numberText(max);
  return s;
}

// Why v (typed as `text`) is not a number of `rule`, or "".
std::string numberProblem(double v, const std::string& text, NumberRule rule, double max) {
  bool ok = std::isfinite(v) && v <= max && (rule == NumberRule::AboveZero ? v > 0.0 : v >= 0.0);
  if (!ok) return "expected " + ruleText(rule, max) + ", got '" + text + "'";
  // 1e-50 is not 0 (which often means "keep") nor a positive exposure once it is a float.
  if (v != 0.0 && float(v) == 0.0f)
    return "expected " + ruleText(rule, max) + " that is not 0 as a float, got '" + text + "'";
  return "";
}

float checkNumberText(const std::string& option, double v, const std::string& text, NumberRule rule,
                      double max) {
  std::string why = numberProblem(v, text, rule, max);
  if (!why.empty()) throw Error(option + ": " + why);
  return float(v);
}

}  // namespace

void badOptionValue(const std::string& option, const std::string& value, const std::string& what) {
  throw Error(option + ": " + what + ", got '" + shortText(value) + "'");
}

std::string trimmed(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace((unsigned char)s[b])) ++b;
  while (e > b && std::isspace((unsigned char)s[e - 1])) --e;
  return s.substr(b, e - b);
}

float checkNumber(const std::string& option, double value, NumberRule rule, double max) {
  return checkNumberText(option, value, numberText(value), rule, max);
}

long long checkInteger(const std::string& option, long long value, long long lo, long long hi) {
  if (value < lo || value > hi)
    badOptionValue(option, std::to_string(value),
                   "expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  return value;
}

std::string numberTextProblem(const std::string& text, NumberRule rule, double max) {
  std::string s = trimmed(text);
  char* end = nullptr;
  double v = s.empty() ? 0.0 : std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return "expected a number, got '" + text + "'";
  return numberProblem(v, text, rule, max);
}

float parseNumber(const std::string& option, const std::string& text, NumberRule rule, double max) {
  std::string why = numberTextProblem(text, rule, max);
  if (!why.empty()) throw Error(option + ": " + why);
  return float(std::strtod(trimmed(text).c_str(), nullptr));
}

long long parseInteger(const std::string& option, const std::string& text, long long lo,
                       long long hi) {
  std::string s = trimmed(text);
  static const std::regex form(R"([-+]?\d{1,18})");
  if (!std::regex_match(s, form)) badOptionValue(option, text, "expected an integer");
  long long v = std::strtoll(s.c_str(), nullptr, 10);
  if (v < lo || v > hi)
    badOptionValue(option, text,
                   "expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

std::pair<int, int> parseTileSize(const std::string& text) {
  std::smatch m;
  std::string s = trimmed(text);
  static const std::regex form(R"((\d{1,6})(?:[xX](\d{1,6}))?)");
  if (!std::regex_match(s, m, form))
    badOptionValue("--tile", text, "expected N or WxH (e.g. 16 or 32x16)");
  int w = std::atoi(m[1].str().c_str()), h = m[2].matched ? std::atoi(m[2].str().c_str()) : w;
  if (w < 1 || h < 1 || w > kMaxTileSide || h > kMaxTileSide)
    badOptionValue("--tile", text, "tile sides must be within 1.." + std::to_string(kMaxTileSide));
  return {w, h};
}

std::pair<int, int> parseResolution(const std::string& text) {
  std::smatch m;
  std::string s = trimmed(text);
  static const std::regex form(R"((\d{1,6})[xX](\d{1,6}))");
  if (!std::regex_match(s, m, form))
    badOptionValue("--resolution", text, "expected WxH (e.g. 1280x720)");
  int w = std::atoi(m[1].str().c_str()), h = std::atoi(m[2].str().c_str());
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    badOptionValue("--resolution", text,
                   "sides must be within 1.." + std::to_string(kMaxImageSide));
  return {w, h};
}

std::vector<std::string> splitList(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) {
    item = trimmed(item);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace ts
