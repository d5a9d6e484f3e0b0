#include "specht/core/text.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>

namespace specht {
namespace {

// The code points our labels use, sorted by code point for a binary search.
constexpr std::array<std::pair<char32_t, const char*>, 48> kSpellings = {{
    {0x00A0, " "},     {0x00B0, "deg"}, {0x00B1, "+/-"},   {0x00B2, "2"},   {0x00B3, "3"},   {0x00B5, "u"},
    {0x00B7, "."},     {0x00BC, "1/4"}, {0x00BD, "1/2"},   {0x00BE, "3/4"}, {0x00C0, "A"},   {0x00C9, "E"},
    {0x00D7, "x"},     {0x00DF, "ss"},  {0x00E0, "a"},     {0x00E1, "a"},   {0x00E2, "a"},   {0x00E4, "a"},
    {0x00E7, "c"},     {0x00E8, "e"},   {0x00E9, "e"},     {0x00EA, "e"},   {0x00EB, "e"},   {0x00EE, "i"},
    {0x00EF, "i"},     {0x00F4, "o"},   {0x00F6, "o"},     {0x00F9, "u"},   {0x00FB, "u"},   {0x00FC, "u"},
    {0x03B1, "alpha"}, {0x03C1, "rho"}, {0x03C3, "sigma"}, {0x2010, "-"},   {0x2013, "-"},   {0x2014, "-"},
    {0x2018, "'"},     {0x2019, "'"},   {0x201C, "\""},    {0x201D, "\""},  {0x2026, "..."}, {0x2153, "1/3"},
    {0x215B, "1/8"},   {0x2192, "->"},  {0x2212, "-"},     {0x2248, "~"},   {0x2264, "<="},  {0x2265, ">="},
}};

constexpr bool StrictlySorted() {
  for (size_t i = 1; i < kSpellings.size(); ++i) {
    if (!(kSpellings[i - 1].first < kSpellings[i].first)) return false;
  }
  return true;
}
static_assert(StrictlySorted(), "kSpellings: sorted by code point, every entry filled");

// Decodes the code point at s[i] and advances i; false (i advanced by one byte)
// for a malformed or truncated sequence.
bool NextCodePoint(std::string_view s, size_t& i, char32_t& cp) {
  const auto b0 = static_cast<uint8_t>(s[i]);
  const int extra = b0 >= 0xC2 && b0 <= 0xDF ? 1 : b0 >= 0xE0 && b0 <= 0xEF ? 2 : b0 >= 0xF0 && b0 <= 0xF4 ? 3 : -1;
  if (extra < 0 || i + extra >= s.size()) {
    ++i;
    return false;
  }
  cp = b0 & (0x3F >> extra);
  for (int k = 1; k <= extra; ++k) {
    const auto b = static_cast<uint8_t>(s[i + k]);
    if ((b & 0xC0) != 0x80) {
      ++i;
      return false;
    }
    cp = (cp << 6) | (b & 0x3F);
  }
  i += extra + 1;
  return true;
}

}  // namespace

std::string AsciiForImage(std::string_view utf8) {
  std::string out;
  out.reserve(utf8.size());
  for (size_t i = 0; i < utf8.size();) {
    if (static_cast<uint8_t>(utf8[i]) < 0x80) {
      out += utf8[i++];
      continue;
    }
    char32_t cp = 0;
    if (!NextCodePoint(utf8, i, cp)) {
      out += '?';
      continue;
    }
    const auto it = std::lower_bound(kSpellings.begin(), kSpellings.end(), cp,
                                     [](const auto& entry, char32_t c) { return entry.first < c; });
    out += it != kSpellings.end() && it->first == cp ? it->second : "?";
  }
  return out;
}

}  // namespace specht
