#include "longterm_mapper2d/core/io/relations_reader.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace longterm_mapper2d {
namespace {

// Parses a whole token as a finite double; "1.5abc", "nan" and "inf" are rejected.
bool ParseFiniteDouble(const std::string& token, double& value) {
  const char* begin = token.c_str();
  char* end = nullptr;
  value = std::strtod(begin, &end);
  return end != begin && *end == '\0' && std::isfinite(value);
}

}  // namespace

StatusOr<std::vector<Relation>> ParseRelations(const std::string& text,
                                               const std::string& source_name) {
  std::istringstream in(text);
  std::vector<Relation> relations;
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
    if (tokens.size() != 8) {
      return Status::Error(where + "expected 8 fields 't1 t2 x y z roll pitch yaw', got " +
                           std::to_string(tokens.size()));
    }
    double values[8];
    for (int i = 0; i < 8; ++i) {
      if (!ParseFiniteDouble(tokens[i], values[i])) {
        return Status::Error(where + "field " + std::to_string(i + 1) + " '" + tokens[i] +
                             "' is not a finite number");
      }
    }
    relations.push_back({values[0], values[1], Pose2(values[2], values[3], values[7])});
  }
  return relations;
}

StatusOr<std::vector<Relation>> ReadRelations(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error("cannot open relations file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Status::Error("error while reading '" + path + "'");
  return ParseRelations(text.str(), path);
}

}  // namespace longterm_mapper2d
