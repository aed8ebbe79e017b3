// The helpers behind every JSON input (issue #16 items 6, 9 and 13): the strict parser refuses
// duplicate keys, NUL and nesting beyond 64 levels in one short line (src/util/strict_json.h),
// long echoes are cut short (short_text.h), and a directory or missing file is one line naming it
// (file_read.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "json_errors.h"
#include "test_support.h"
#include "util/error.h"
#include "util/file_read.h"
#include "util/short_text.h"
#include "util/strict_json.h"

namespace fs = std::filesystem;

namespace {

using ts::test::errorOf;
using ts::test::errorOfParse;
using ts::test::expectMessage;
using ts::test::nested;
using ts::test::writeText;

fs::path freshDir(const std::string& name) { return ts::test::freshDir("json_input", name); }

TEST(ShortText, KeepsShortTextAndCutsLongTextWithItsLength) {
  EXPECT_EQ(ts::shortText("tiled"), "tiled");
  const std::string cut = ts::shortText(std::string(1 << 20, 'k'));
  EXPECT_EQ(cut, std::string(ts::kShortTextChars, 'k') + "\xE2\x80\xA6 (1048576 bytes)");
  EXPECT_EQ(ts::shortText("a\nb\tc\x01"), "a\\nb\\tc\\x01");  // one line, whatever the input
  // A cut never splits a UTF-8 character: "é" (2 bytes) at bytes 59-60 is left out whole.
  const std::string accents = "a" + std::string(100, 'x').replace(58, 2, "\xC3\xA9");
  const std::string s = ts::shortText(accents);
  EXPECT_EQ(s, accents.substr(0, 59) + "\xE2\x80\xA6 (101 bytes)");
}

TEST(StrictJson, DuplicateKeysAreErrorsAtAnyDepth) {
  expectMessage(errorOfParse("{\"a\": 1, \"a\": 2}"), {"src: ", "\"a\" appears twice"});
  expectMessage(errorOfParse("{\"x\": [{\"b\": 1, \"c\": {}, \"b\": 0}]}"),
                {"\"b\" appears twice"});
  // The same key in sibling objects is fine.
  EXPECT_EQ(errorOfParse("[{\"a\": 1}, {\"a\": 2}, {\"o\": {\"a\": 3}, \"a\": 4}]"), "");
}

TEST(StrictJson, NestingIsRefusedBeyond64LevelsWhileParsing) {
  EXPECT_EQ(errorOfParse(nested(ts::kMaxJsonDepth)), "");
  expectMessage(errorOfParse(nested(ts::kMaxJsonDepth + 1)), {"nested deeper than 64"});
  expectMessage(errorOfParse("{\"a\":" + std::string(100000, '[')), {"nested deeper than 64"});
  // Objects count too; an unterminated 10 MB nesting is refused at level 65.
  std::string objects;
  for (int i = 0; i < 70; ++i) objects += "{\"k\":";
  expectMessage(errorOfParse(objects), {"nested deeper than 64"});
  expectMessage(errorOfParse(std::string(10 << 20, '[')), {"nested deeper than 64"});
}

TEST(StrictJson, NulInAStringOrKeyIsAnError) {
  expectMessage(errorOfParse(R"({"image": "gbuffer.exr\u0000.png"})"),
                {"\\u0000", "gbuffer.exr\\x00.png"});
  expectMessage(errorOfParse(R"({"a\u0000b": 1})"), {"\\u0000"});
  EXPECT_EQ(errorOfParse(R"({"a": "\u0001 is fine"})"), "");
}

TEST(StrictJson, SyntaxErrorsAreShortAndSayWhere) {
  expectMessage(errorOfParse(""), {"src: not valid JSON: ", "line 1, column 1"});
  expectMessage(errorOfParse("{\"a\": \"" + std::string(1 << 20, 'z')),  // unterminated
                {"src: not valid JSON"});
  expectMessage(errorOfParse("{\"a\": " + std::string(1 << 20, '7') + "x}"), {"not valid JSON"});
  // Comments only where asked for (bench configs).
  EXPECT_NE(errorOfParse("{\"a\": 1 /* c */}"), "");
  EXPECT_NO_THROW(ts::parseStrictJson("{\"a\": 1 /* c */}", "src", ts::JsonComments::Allowed));
}

TEST(ReadTextFile, DirectoriesAndMissingFilesAreOneLineNamingThePath) {
  const fs::path dir = freshDir("read_dir");
  expectMessage(errorOf([&] { ts::readTextFile(dir.string(), "bench config"); }),
                {"cannot read bench config " + dir.string() + ": it is a directory"});
  expectMessage(errorOf([&] { ts::readTextFile((dir / "none").string(), "lights file"); }),
                {"cannot read lights file " + (dir / "none").string() + ": no such file"});
  writeText(dir / "f.json", "{\"a\": [1]}");
  EXPECT_EQ(ts::readJsonFile((dir / "f.json").string(), "x").at("a").at(0), 1);
}

}  // namespace
