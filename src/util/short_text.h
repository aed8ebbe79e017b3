#pragma once
// User text quoted in a message, bounded: an error line that echoes an input (an unknown key, a
// value, an option, a channel name) stays one short line however long or odd the input is.
#include <cstddef>
#include <string>

namespace ts {

constexpr size_t kShortTextChars = 60;

// `text` with control characters escaped (\n, \t, \xNN) so the message stays one line; when
// longer than `keep` bytes, its first `keep` bytes (not splitting a UTF-8 character), "…" and
// its length, e.g. `aaaa… (1048576 bytes)`.
std::string shortText(const std::string& text, size_t keep = kShortTextChars);

}  // namespace ts
