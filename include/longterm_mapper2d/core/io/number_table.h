#pragma once

#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"

namespace longterm_mapper2d {

// One data line of a whitespace-separated table of numbers.
struct NumberRow {
  int line_number = 0;  // 1-based, in the source
  std::vector<double> values;
};

// Parses the text tables the tools exchange (trajectories, trajectory anchors, benchmark
// relations): blank lines and lines whose first non-blank character is '#' are skipped; every
// other line must hold exactly `columns` finite numbers, each a whole token ("1.5abc", "nan" and
// "inf" are refused). Errors start with "source_name:line: " and say what the line should hold
// (`layout`, e.g. "'stamp x y theta'").
StatusOr<std::vector<NumberRow>> ParseNumberTable(const std::string& text,
                                                  const std::string& source_name, int columns,
                                                  const std::string& layout);

// The same, where a line may hold any of the `allowed` numbers of fields (a table with
// optional trailing columns).
StatusOr<std::vector<NumberRow>> ParseNumberTable(const std::string& text,
                                                  const std::string& source_name,
                                                  const std::vector<int>& allowed,
                                                  const std::string& layout);

// Reads the file at `path` whole and parses it as above.
StatusOr<std::vector<NumberRow>> ReadNumberTable(const std::string& path, int columns,
                                                 const std::string& layout);
StatusOr<std::vector<NumberRow>> ReadNumberTable(const std::string& path,
                                                 const std::vector<int>& allowed,
                                                 const std::string& layout);

}  // namespace longterm_mapper2d
