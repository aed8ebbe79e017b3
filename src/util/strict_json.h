#pragma once
// Every JSON file tileshade reads is parsed by these rules, checked while parsing (nothing deep
// or doubtful is ever built): a key twice in one object is an error (nlohmann keeps the last one
// silently: "lights" twice dropped every light), so is nesting deeper than kMaxJsonDepth (a
// 100,000-deep value crashed the recursive code after the parser) and a string holding NUL
// (a path would be cut at it). Error messages quote the input through shortText.
#include <string>

#include <nlohmann/json.hpp>

namespace ts {

constexpr int kMaxJsonDepth = 64;  // the glTF loader's limit since issue #12

enum class JsonComments { Refused, Allowed };

// Parses `text`; throws ts::Error "SOURCE: WHY" (SOURCE names the file, e.g. "bench config x").
nlohmann::json parseStrictJson(const std::string& text, const std::string& source,
                               JsonComments comments = JsonComments::Refused);

// readTextFile(path, what), then parseStrictJson with source "PATH".
nlohmann::json readJsonFile(const std::string& path, const std::string& what,
                            JsonComments comments = JsonComments::Refused);

}  // namespace ts
