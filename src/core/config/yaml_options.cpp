#include "longterm_mapper2d/core/config/yaml_options.h"

#include <fstream>
#include <sstream>

namespace longterm_mapper2d {

Status ReadTextFile(const std::string& path, std::string& text) {
  std::ifstream in(path);
  if (!in) return Status::Error("cannot open '" + path + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Status::Error("error while reading '" + path + "'");
  text = buffer.str();
  return Status::Ok();
}

}  // namespace longterm_mapper2d
