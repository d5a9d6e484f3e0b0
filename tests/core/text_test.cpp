#include "specht/core/text.h"

#include <gtest/gtest.h>

namespace specht {
namespace {

TEST(AsciiForImageTest, SpellsOurSymbolsInAscii) {
  EXPECT_EQ(AsciiForImage("tiny: 5-fold CV × 3 by MMSI, pooled"), "tiny: 5-fold CV x 3 by MMSI, pooled");
  EXPECT_EQ(AsciiForImage("0.747 ± 0.084, −0.038, ≥ 0.80, 12°"), "0.747 +/- 0.084, -0.038, >= 0.80, 12deg");
  EXPECT_EQ(AsciiForImage("⅛ ¼ ½ of the vessels → Brest"), "1/8 1/4 1/2 of the vessels -> Brest");
  EXPECT_EQ(AsciiForImage("Saint-Nazaire, Lézardrieux"), "Saint-Nazaire, Lezardrieux");
}

TEST(AsciiForImageTest, PassesAsciiAndMarksTheRest) {
  const std::string ascii = "plain ASCII: 0-9, [a/b] {x=1}";
  EXPECT_EQ(AsciiForImage(ascii), ascii);
  EXPECT_EQ(AsciiForImage(""), "");
  EXPECT_EQ(AsciiForImage("日本"), "??");        // characters without a spelling: one '?' each
  EXPECT_EQ(AsciiForImage("a\xC3"), "a?");       // truncated two-byte sequence
  EXPECT_EQ(AsciiForImage("\xE2\x88"), "??");    // truncated three-byte sequence: '?' per byte
  EXPECT_EQ(AsciiForImage("\x80x\xFF"), "?x?");  // stray continuation byte, invalid lead byte
  EXPECT_EQ(AsciiForImage("\xC3(b"), "?(b");     // lead byte followed by a non-continuation byte
}

}  // namespace
}  // namespace specht
