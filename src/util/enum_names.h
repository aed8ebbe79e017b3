#pragma once
// One name table per configuration knob (culling test, G-buffer layout, rasterizer, ...): the
// command line, bench's dimensions and config files, check, stats.json, the CSV columns and
// --help all parse and print a knob's values through its table, so they cannot disagree. A new
// value is one row.
#include <string>
#include <utility>
#include <vector>

#include "util/error.h"
#include "util/option_values.h"
#include "util/short_text.h"

namespace ts {

// One value of a knob: its name on the command line and in files, and a few words for --help.
template <typename E>
struct EnumName {
  E value;
  const char* name;
  const char* help = "";  // "" = the name says it
};

template <typename E>
class EnumNames {
 public:
  // `what` names the knob in errors ("culling test").
  EnumNames(std::string what, std::vector<EnumName<E>> entries)
      : what_(std::move(what)), entries_(std::move(entries)) {}

  // The value called `name` exactly; throws ts::Error "unknown WHAT 'NAME' (known: a, b, c)".
  E parse(const std::string& name) const {
    if (const EnumName<E>* e = find(name)) return e->value;
    throw Error("unknown " + what_ + " '" + shortText(name) + "' (known: " + list() + ")");
  }
  // An option's value, surrounding spaces allowed; throws the one form of a bad option value,
  // "OPTION: expected one of a, b, c, got 'TEXT'".
  E parseOption(const std::string& option, const std::string& text) const {
    if (const EnumName<E>* e = find(trimmed(text))) return e->value;
    badOptionValue(option, text, "expected one of " + list());
  }
  // "?" for a value that has no row (a cast from a bad int).
  const char* name(E value) const {
    for (const auto& e : entries_)
      if (e.value == value) return e.name;
    return "?";
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : entries_) out.push_back(e.name);
    return out;
  }
  // "a, b, c"
  std::string list() const { return joined(false); }
  // "a (what a does), b, c (...)": the values for --help.
  std::string help() const { return joined(true); }
  const std::vector<EnumName<E>>& entries() const { return entries_; }
  const std::string& what() const { return what_; }

 private:
  const EnumName<E>* find(const std::string& name) const {
    for (const auto& e : entries_)
      if (name == e.name) return &e;
    return nullptr;
  }
  std::string joined(bool withHelp) const {
    std::string s;
    for (const auto& e : entries_) {
      s += (s.empty() ? "" : ", ") + std::string(e.name);
      if (withHelp && *e.help) s += std::string(" (") + e.help + ")";
    }
    return s;
  }

  std::string what_;
  std::vector<EnumName<E>> entries_;
};

// A knob that is on or off, in sweeps and files (bench's depth_split; JSON true and false read as
// these names).
inline const EnumNames<bool>& switchNames() {
  static const EnumNames<bool> names("switch value", {{false, "false"}, {true, "true"}});
  return names;
}

}  // namespace ts
