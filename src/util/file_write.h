#pragma once
// Checked file writes: every output file of tileshade (images, stats.json, lights.json, bench
// CSV/JSON, glTF export) goes through these, so a full disk, an unwritable folder or a short write
// is a ts::Error naming the file and the reason ("No space left on device"), never a truncated
// file reported as written.
#include <cstddef>
#include <ostream>
#include <string>

namespace ts {

// Creates or truncates `path` and writes the bytes; throws ts::Error on any failure, including
// one reported only when the file is closed.
void writeFile(const std::string& path, const void* data, size_t size);
void writeFile(const std::string& path, const std::string& text);

// Writes `path`.tmp, then renames it over `path`: a reader never sees a half-written file.
void writeFileAtomically(const std::string& path, const std::string& text);

// For files written a piece at a time through a stream (bench.csv rows): flushes and throws
// ts::Error naming `path` when the stream failed.
void flushChecked(std::ostream& out, const std::string& path);

}  // namespace ts
