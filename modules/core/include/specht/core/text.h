// specht/core/text.h: text for pictures. OpenCV's Hershey fonts draw ASCII only
// (every other byte becomes a '?' box), while our titles and labels are UTF-8
// ("5-fold CV × 3", "0.75 ± 0.08", "½"). Drawn text goes through AsciiForImage.
#pragma once

#include <string>
#include <string_view>

namespace specht {

// `utf8` with the symbols our labels use spelt in ASCII (× → x, − and dashes → -,
// ± → +/-, ° → deg, ≥ → >=, fractions → 1/2, accented Latin letters without the
// accent, …); any other non-ASCII character, and each byte of malformed UTF-8,
// becomes '?'. ASCII passes unchanged.
std::string AsciiForImage(std::string_view utf8);

}  // namespace specht
