// Error messages that quote input: control bytes and non-UTF-8 bytes escaped, UTF-8 kept.
#include "core/error.hpp"

#include <gtest/gtest.h>

namespace weft {
namespace {

TEST(Error, PrintableTextEscapesWhatATerminalWouldInterpret) {
  EXPECT_EQ(printable_text("plain text, 1.5 m"), "plain text, 1.5 m");
  EXPECT_EQ(printable_text(std::string("a\x1b[2Jb\x00"
                                       "c",
                                       8)),
            "a\\x1b[2Jb\\x00c");
  EXPECT_EQ(printable_text("\x89PNG\r\n"), "\\x89PNG\\x0d\\x0a");
  EXPECT_EQ(printable_text("sc\xc3\xa8ne_\xe2\x82\xac.json"),
            "sc\xc3\xa8ne_\xe2\x82\xac.json");                   // UTF-8 kept
  EXPECT_EQ(printable_text("\xc3"), "\\xc3");                    // cut short
  EXPECT_EQ(printable_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a surrogate
  EXPECT_EQ(printable_text("\xff\xfe"), "\\xff\\xfe");
}

TEST(Error, ErrorsCarryPrintableMessages) {
  const SceneError error("bin.json", "", "last read: '\xff'");
  EXPECT_STREQ(error.what(), "bin.json: /: last read: '\\xff'");
  EXPECT_STREQ(IoError("x.obj: \x07").what(), "x.obj: \\x07");
}

}  // namespace
}  // namespace weft
