#include "longterm_mapper2d/core/io/g2o_io.h"

#include <cmath>
#include <cstdio>
#include <deque>
#include <set>
#include <sstream>

#include "longterm_mapper2d/core/io/atomic_file.h"

namespace longterm_mapper2d {
namespace {

bool ReadNumbers(std::istringstream& in, double* values, int count) {
  for (int i = 0; i < count; ++i) {
    if (!(in >> values[i]) || !std::isfinite(values[i])) return false;
  }
  return true;
}

}  // namespace

StatusOr<PoseGraph> ParseG2o(const std::string& text, const std::string& source_name,
                             G2oReadReport* report) {
  G2oReadReport local;
  G2oReadReport& r = report ? *report : local;
  std::map<GraphNodeId, Pose2> vertices;
  std::vector<GraphEdge> edges;
  std::set<GraphNodeId> fixed;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  auto error = [&](const std::string& what) {
    return Status::Error(source_name + ":" + std::to_string(line_number) + ": " + what);
  };
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream in(line);
    std::string tag;
    if (!(in >> tag) || tag[0] == '#') continue;
    if (tag == "VERTEX_SE2" || tag == "VERTEX2") {
      long long id;
      double v[3];
      if (!(in >> id) || !ReadNumbers(in, v, 3)) return error("malformed " + tag + " line");
      if (vertices.count(id)) return error("vertex " + std::to_string(id) + " defined twice");
      vertices[id] = Pose2(v[0], v[1], v[2]);
      ++r.vertices;
    } else if (tag == "EDGE_SE2" || tag == "EDGE2") {
      long long from, to;
      double v[9];
      if (!(in >> from >> to) || !ReadNumbers(in, v, 9)) return error("malformed " + tag + " line");
      GraphEdge edge;
      edge.from = from;
      edge.to = to;
      edge.measurement = Pose2(v[0], v[1], v[2]);
      Eigen::Matrix3d& I = edge.information;
      if (tag == "EDGE_SE2") {
        // Upper triangle row by row: I11 I12 I13 I22 I23 I33.
        I << v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8];
      } else {
        // TORO order: I11 I12 I22 I33 I13 I23.
        I << v[3], v[4], v[7], v[4], v[5], v[8], v[7], v[8], v[6];
      }
      // Consecutive ids, written so that no difference of extreme ids can overflow.
      const bool consecutive = (from < to && from + 1 == to) || (to < from && to + 1 == from);
      edge.kind = consecutive ? EdgeKind::kOdometry : EdgeKind::kLoopClosure;
      edges.push_back(edge);
      ++r.edges;
    } else if (tag == "FIX") {
      long long id;
      if (!(in >> id)) return error("malformed FIX line");
      fixed.insert(id);
    } else {
      ++r.skipped_tags[tag];
    }
  }

  // Nodes without a vertex line: breadth first from the lowest id over the edges.
  std::set<GraphNodeId> referenced;
  for (const auto& e : edges) {
    referenced.insert(e.from);
    referenced.insert(e.to);
  }
  std::map<GraphNodeId, std::vector<std::size_t>> adjacency;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    adjacency[edges[i].from].push_back(i);
    adjacency[edges[i].to].push_back(i);
  }
  for (GraphNodeId start : referenced) {
    if (vertices.count(start)) continue;
    // Start a component at the first unplaced node: at the origin unless a placed neighbour
    // exists, which the search reaches from it anyway.
    std::deque<GraphNodeId> queue;
    bool anchored = false;
    for (std::size_t i : adjacency[start]) {
      const GraphNodeId other = edges[i].from == start ? edges[i].to : edges[i].from;
      if (vertices.count(other)) {
        queue.push_back(other);
        anchored = true;
      }
    }
    if (!anchored) {
      vertices[start] = Pose2();
      ++r.vertices_initialised_from_edges;
      queue.push_back(start);
    }
    while (!queue.empty()) {
      const GraphNodeId id = queue.front();
      queue.pop_front();
      for (std::size_t i : adjacency[id]) {
        const GraphEdge& e = edges[i];
        const GraphNodeId other = e.from == id ? e.to : e.from;
        if (vertices.count(other)) continue;
        vertices[other] = e.from == id ? vertices[id] * e.measurement
                                       : vertices[id] * e.measurement.inverse();
        ++r.vertices_initialised_from_edges;
        queue.push_back(other);
      }
    }
  }

  PoseGraph graph;
  for (const auto& [id, pose] : vertices) {
    GraphNode node;
    node.id = id;
    node.pose = pose;
    if (Status s = graph.AddNode(node); !s.ok()) return Status::Error(source_name + ": " + s.message());
  }
  for (const auto& e : edges) {
    if (Status s = graph.AddEdge(e); !s.ok()) return Status::Error(source_name + ": " + s.message());
  }
  if (!fixed.empty() && graph.HasNode(*fixed.begin())) graph.SetGauge(*fixed.begin());
  return graph;
}

StatusOr<PoseGraph> ReadG2o(const std::string& path, G2oReadReport* report) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParseG2o(*bytes, path, report);
}

std::string FormatG2o(const PoseGraph& graph) {
  std::string out;
  char line[512];
  for (const auto& [id, node] : graph.nodes()) {
    std::snprintf(line, sizeof(line), "VERTEX_SE2 %lld %.9g %.9g %.9g\n",
                  static_cast<long long>(id), node.pose.x(), node.pose.y(), node.pose.theta());
    out += line;
  }
  for (const GraphEdge& e : graph.edges()) {
    const Eigen::Matrix3d& I = e.information;
    std::snprintf(line, sizeof(line),
                  "EDGE_SE2 %lld %lld %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n",
                  static_cast<long long>(e.from), static_cast<long long>(e.to), e.measurement.x(),
                  e.measurement.y(), e.measurement.theta(), I(0, 0), I(0, 1), I(0, 2), I(1, 1),
                  I(1, 2), I(2, 2));
    out += line;
  }
  if (graph.gauge()) out += "FIX " + std::to_string(*graph.gauge()) + "\n";
  return out;
}

Status WriteG2o(const PoseGraph& graph, const std::string& path) {
  return WriteFileAtomically(path, FormatG2o(graph));
}

}  // namespace longterm_mapper2d
