#include "util/short_text.h"

#include <cstdio>

namespace ts {
namespace {

void appendEscaped(std::string& out, unsigned char c) {
  if (c == '\n') out += "\\n";
  else if (c == '\t') out += "\\t";
  else if (c == '\r') out += "\\r";
  else if (c < 0x20 || c == 0x7f) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", c);
    out += buf;
  } else {
    out += char(c);
  }
}

}  // namespace

std::string shortText(const std::string& text, size_t keep) {
  size_t end = text.size();
  if (end > keep) {
    end = keep;
    // Back up over UTF-8 continuation bytes so the cut does not split a character.
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  }
  std::string out;
  out.reserve(end + 32);
  for (size_t i = 0; i < end; ++i) appendEscaped(out, static_cast<unsigned char>(text[i]));
  if (end < text.size()) out += "\xE2\x80\xA6 (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace ts
