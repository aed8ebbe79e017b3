#include "util/strict_json.h"

#include <unordered_set>
#include <vector>

#include "util/error.h"
#include "util/file_read.h"
#include "util/short_text.h"

namespace ts {
namespace {

using json = nlohmann::json;

// nlohmann's DOM builder with the strict rules in front of it.
class StrictSax {
 public:
  StrictSax(json& root, const std::string& source) : dom_(root, false), source_(source) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) {
    return dom_.number_float(v, s);
  }
  bool string(json::string_t& s) {
    noNul(s, "a string");
    return dom_.string(s);
  }
  bool binary(json::binary_t& b) { return dom_.binary(b); }
  bool start_object(std::size_t n) {
    enter();
    keys_.emplace_back();
    return dom_.start_object(n);
  }
  bool key(json::string_t& k) {
    noNul(k, "a key");
    if (!keys_.back().insert(k).second)
      fail("key \"" + shortText(k) + "\" appears twice in one object");
    return dom_.key(k);
  }
  bool end_object() {
    --depth_;
    keys_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t n) {
    enter();
    return dom_.start_array(n);
  }
  bool end_array() {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line 1, column 2: WHY; last
    // read: 'TOKEN'": the token may be the whole input, so the reason is shortened.
    std::string why = e.what();
    const size_t at = why.find("] ");
    if (at != std::string::npos) why.erase(0, at + 2);
    fail("not valid JSON: " + shortText(why, 160));
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw Error(source_ + ": " + why); }
  void enter() {
    if (++depth_ > kMaxJsonDepth)
      fail("JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  }
  void noNul(const std::string& s, const char* what) const {
    if (s.find('\0') != std::string::npos)
      fail(std::string(what) + " holds \\u0000 (NUL), which would cut a name short: \"" +
           shortText(s) + "\"");
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  const std::string& source_;
  int depth_ = 0;
  std::vector<std::unordered_set<std::string>> keys_;  // per open object
};

}  // namespace

json parseStrictJson(const std::string& text, const std::string& source, JsonComments comments) {
  json root;
  StrictSax sax(root, source);
  json::sax_parse(text, &sax, json::input_format_t::json, /*strict=*/true,
                  comments == JsonComments::Allowed);
  return root;
}

json readJsonFile(const std::string& path, const std::string& what, JsonComments comments) {
  return parseStrictJson(readTextFile(path, what), shortText(path, 200), comments);
}

}  // namespace ts
