// specht/core/csv.h: splitting one CSV line (RFC 4180 quoting: a quoted cell may
// hold commas, and "" inside quotes is one quote). Cells are trimmed of surrounding
// spaces and a trailing '\r'; "a," gives two cells.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace specht {

// Reuses `cells` (cleared first) so a reader looping over lines does not allocate.
void SplitCsv(std::string_view line, std::vector<std::string>& cells);
std::vector<std::string> SplitCsv(std::string_view line);

}  // namespace specht
