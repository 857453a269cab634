#include "longterm_mapper2d/core/io/relations_reader.h"

#include "longterm_mapper2d/core/io/number_table.h"

namespace longterm_mapper2d {
namespace {

constexpr char kLayout[] = "'t1 t2 x y z roll pitch yaw'";

std::vector<Relation> ToRelations(const std::vector<NumberRow>& rows) {
  std::vector<Relation> relations;
  relations.reserve(rows.size());
  for (const NumberRow& row : rows) {
    const std::vector<double>& v = row.values;
    relations.push_back({v[0], v[1], Pose2(v[2], v[3], v[7])});
  }
  return relations;
}

}  // namespace

StatusOr<std::vector<Relation>> ParseRelations(const std::string& text,
                                               const std::string& source_name) {
  const auto rows = ParseNumberTable(text, source_name, 8, kLayout);
  if (!rows.ok()) return rows.status();
  return ToRelations(*rows);
}

StatusOr<std::vector<Relation>> ReadRelations(const std::string& path) {
  const auto rows = ReadNumberTable(path, 8, kLayout);
  if (!rows.ok()) return rows.status();
  return ToRelations(*rows);
}

}  // namespace longterm_mapper2d
