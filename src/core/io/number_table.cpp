#include "longterm_mapper2d/core/io/number_table.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace longterm_mapper2d {
namespace {

// A whole token as a finite double.
bool ParseFiniteDouble(const std::string& token, double& value) {
  const char* begin = token.c_str();
  char* end = nullptr;
  value = std::strtod(begin, &end);
  return end != begin && *end == '\0' && std::isfinite(value);
}

}  // namespace

StatusOr<std::vector<NumberRow>> ParseNumberTable(const std::string& text,
                                                  const std::string& source_name, int columns,
                                                  const std::string& layout) {
  return ParseNumberTable(text, source_name, std::vector<int>{columns}, layout);
}

StatusOr<std::vector<NumberRow>> ParseNumberTable(const std::string& text,
                                                  const std::string& source_name,
                                                  const std::vector<int>& allowed,
                                                  const std::string& layout) {
  std::istringstream in(text);
  std::vector<NumberRow> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = source_name + ":" + std::to_string(line_number) + ": ";
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;) tokens.push_back(token);
    if (std::find(allowed.begin(), allowed.end(), static_cast<int>(tokens.size())) ==
        allowed.end()) {
      std::string counts;
      for (std::size_t i = 0; i < allowed.size(); ++i) {
        counts += (i == 0                    ? ""
                   : i + 1 == allowed.size() ? " or "
                                             : ", ") +
                  std::to_string(allowed[i]);
      }
      return Status::Error(where + "expected " + counts + " fields " + layout + ", got " +
                           std::to_string(tokens.size()));
    }
    NumberRow row;
    row.line_number = line_number;
    row.values.resize(tokens.size());
    for (std::size_t i = 0; i < tokens.size(); ++i) {
      if (!ParseFiniteDouble(tokens[i], row.values[i])) {
        return Status::Error(where + "field " + std::to_string(i + 1) + " '" + tokens[i] +
                             "' is not a finite number");
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

StatusOr<std::vector<NumberRow>> ReadNumberTable(const std::string& path, int columns,
                                                 const std::string& layout) {
  return ReadNumberTable(path, std::vector<int>{columns}, layout);
}

StatusOr<std::vector<NumberRow>> ReadNumberTable(const std::string& path,
                                                 const std::vector<int>& allowed,
                                                 const std::string& layout) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error("cannot open '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Status::Error("error while reading '" + path + "'");
  return ParseNumberTable(text.str(), path, allowed, layout);
}

}  // namespace longterm_mapper2d
