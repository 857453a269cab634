#include "longterm_mapper2d/core/map/session_map_file.h"

#include <cstring>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/binary_io.h"

namespace longterm_mapper2d {
namespace {

// Per-point flag bits (version 5).
constexpr std::uint8_t kPointInherited = 1;

constexpr char kMagic[8] = {'L', 'T', 'M', 'A', 'P', '2', 'D', '\n'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 4;
constexpr std::size_t kMaxFrameIdBytes = 256;

void WritePose(BinaryWriter& w, const Pose2& pose) {
  w.Write(pose.x());
  w.Write(pose.y());
  w.Write(pose.theta());
}

// A symmetric 3x3 matrix: its upper triangle, row by row.
void WriteUpperTriangle(BinaryWriter& w, const Eigen::Matrix3d& m) {
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) w.Write(m(i, j));
  }
}

bool ReadUpperTriangle(BinaryReader& r, Eigen::Matrix3d& m, const char* what) {
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      if (!r.Read(m(i, j), what)) return false;
      m(j, i) = m(i, j);
    }
  }
  return true;
}

bool ReadPose(BinaryReader& r, Pose2& pose, const char* what) {
  double x, y, theta;
  if (!r.Read(x, what) || !r.Read(y, what) || !r.Read(theta, what)) return false;
  pose = Pose2(x, y, theta);
  if (!pose.IsFinite()) {
    r.Fail(std::string("non-finite ") + what);
    return false;
  }
  // Saved angles are normalised; another one would change on the next save.
  if (pose.theta() != theta) {
    r.Fail(std::string("angle outside (-pi, pi] in ") + what);
    return false;
  }
  return true;
}

void WriteScan(BinaryWriter& w, const LaserScan& scan) {
  w.Write(scan.stamp_s);
  w.WriteString(scan.frame_id);
  w.Write(scan.angle_min_rad);
  w.Write(scan.angle_increment_rad);
  w.Write(scan.range_min_m);
  w.Write(scan.range_max_m);
  w.Write<std::uint64_t>(scan.ranges.size());
  for (float r : scan.ranges) w.Write(r);
}

bool ReadScan(BinaryReader& r, LaserScan& scan) {
  std::uint64_t beams = 0;
  if (!r.Read(scan.stamp_s, "scan stamp") ||
      !r.ReadString(scan.frame_id, kMaxFrameIdBytes, "scan frame id") ||
      !r.Read(scan.angle_min_rad, "scan angle") || !r.Read(scan.angle_increment_rad, "scan angle") ||
      !r.Read(scan.range_min_m, "scan range") || !r.Read(scan.range_max_m, "scan range") ||
      !r.ReadCount(beams, sizeof(float), "scan beams")) {
    return false;
  }
  scan.ranges.resize(beams);
  for (float& range : scan.ranges) {
    if (!r.Read(range, "scan ranges")) return false;
  }
  return true;
}

}  // namespace

std::string SerializeSessionMap(const SessionMap& map) {
  BinaryWriter payload;
  payload.Write<std::int32_t>(map.sessions);
  payload.Write<std::int64_t>(map.gauge);
  WritePose(payload, map.origin);
  payload.Write<std::uint64_t>(map.nodes.size());
  for (const auto& [id, node] : map.nodes) {
    payload.Write<std::int64_t>(node.id);
    payload.Write<std::int32_t>(node.session_id);
    payload.Write(node.stamp_s);
    WritePose(payload, node.map_T_node);
    payload.Write<std::uint64_t>(node.cloud.size());
    for (const RichPoint& p : node.cloud) {
      payload.Write(p.point_m.x());
      payload.Write(p.point_m.y());
      payload.Write(p.normal.x());
      payload.Write(p.normal.y());
      payload.Write(p.weight);
      payload.Write<std::uint8_t>(p.inherited ? kPointInherited : 0);
    }
    payload.Write<std::uint64_t>(node.waypoints.size());
    for (const Waypoint& w : node.waypoints) {
      WritePose(payload, w.node_T_base);
      WritePose(payload, w.base_T_laser);
      payload.Write<std::int32_t>(w.session_id);
      WriteScan(payload, w.scan);
    }
  }
  payload.Write<std::uint64_t>(map.edges.size());
  for (const GraphEdge& e : map.edges) {
    payload.Write<std::int64_t>(e.from);
    payload.Write<std::int64_t>(e.to);
    payload.Write<std::uint8_t>(static_cast<std::uint8_t>(e.kind));
    payload.Write<std::int32_t>(e.session_id);
    payload.Write(e.stamp_s);
    WritePose(payload, e.measurement);
    WriteUpperTriangle(payload, e.information);
    payload.Write<std::uint8_t>(e.gating_information ? 1 : 0);
    if (e.gating_information) WriteUpperTriangle(payload, *e.gating_information);
  }
  payload.Write<std::uint64_t>(map.removed_nodes.size());
  for (const auto& [id, removed] : map.removed_nodes) {
    payload.Write<std::int64_t>(id);
    payload.Write<std::int64_t>(removed.survivor);
    WritePose(payload, removed.survivor_T_removed);
  }
  const std::string& body = payload.bytes();
  BinaryWriter file;
  file.WriteBytes(std::string(kMagic, sizeof(kMagic)));
  file.Write<std::uint32_t>(kSessionMapVersion);
  file.Write<std::uint64_t>(body.size());
  file.Write<std::uint32_t>(Crc32(body.data(), body.size()));
  file.WriteBytes(body);
  return file.TakeBytes();
}

StatusOr<SessionMap> ParseSessionMap(const std::string& bytes, const std::string& source) {
  auto fail = [&](const std::string& why) {
    return Status::Error("cannot load session map '" + source + "': " + why);
  };
  if (bytes.size() < kHeaderBytes) return fail("file too short for the header (truncated?)");
  if (std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return fail("not a session map file (bad magic)");
  }
  BinaryReader header(bytes.data() + sizeof(kMagic), kHeaderBytes - sizeof(kMagic));
  std::uint32_t version = 0, crc = 0;
  std::uint64_t payload_size = 0;
  header.Read(version, "version");
  header.Read(payload_size, "payload size");
  header.Read(crc, "checksum");
  if (version > kSessionMapVersion) {
    return fail("format version " + std::to_string(version) + " is newer than this build reads (" +
                std::to_string(kSessionMapVersion) + ")");
  }
  if (version == 0) return fail("invalid format version 0");
  if (payload_size != bytes.size() - kHeaderBytes) {
    return fail("payload is " + std::to_string(bytes.size() - kHeaderBytes) + " bytes, header says " +
                std::to_string(payload_size) + " (truncated or extended)");
  }
  const char* body = bytes.data() + kHeaderBytes;
  if (Crc32(body, payload_size) != crc) return fail("checksum mismatch (corrupted)");

  BinaryReader r(body, payload_size);
  SessionMap map;
  std::int32_t sessions = 0;
  std::int64_t gauge = 0;
  std::uint64_t node_count = 0;
  r.Read(sessions, "session count");
  r.Read(gauge, "gauge");
  if (version >= 2) ReadPose(r, map.origin, "origin");
  // A node takes at least 8 + 4 + 8 + 24 + 8 + 8 bytes.
  r.ReadCount(node_count, 60, "nodes");
  map.sessions = sessions;
  map.gauge = gauge;
  for (std::uint64_t n = 0; n < node_count && r.ok(); ++n) {
    LocalMapNode node;
    std::int64_t id = 0;
    std::int32_t session = 0;
    std::uint64_t points = 0, waypoints = 0;
    r.Read(id, "node id");
    r.Read(session, "node session");
    r.Read(node.stamp_s, "node stamp");
    ReadPose(r, node.map_T_node, "node pose");
    const std::size_t point_bytes = 5 * sizeof(double) + (version >= 5 ? 1 : 0);
    r.ReadCount(points, point_bytes, "cloud points");
    if (!r.ok()) break;
    node.id = id;
    node.session_id = session;
    node.cloud.resize(points);
    for (RichPoint& p : node.cloud) {
      double v[5];
      for (double& x : v) r.Read(x, "cloud point");
      p.point_m = Eigen::Vector2d(v[0], v[1]);
      p.normal = Eigen::Vector2d(v[2], v[3]);
      p.weight = v[4];
      // Before version 5 points had no flags: all the node's own.
      std::uint8_t flags = 0;
      if (version >= 5 && r.Read(flags, "cloud point flags") && (flags & ~kPointInherited) != 0) {
        r.Fail("unknown cloud point flags " + std::to_string(flags));
      }
      p.inherited = (flags & kPointInherited) != 0;
    }
    r.ReadCount(waypoints, 100, "waypoints");  // two poses and an empty scan
    if (!r.ok()) break;
    node.waypoints.resize(waypoints);
    for (Waypoint& w : node.waypoints) {
      if (!ReadPose(r, w.node_T_base, "waypoint pose") ||
          !ReadPose(r, w.base_T_laser, "waypoint laser pose")) {
        break;
      }
      // Before version 3 waypoints had no session of their own: the node's is the best guess.
      std::int32_t waypoint_session = session;
      if (version >= 3 && !r.Read(waypoint_session, "waypoint session")) break;
      w.session_id = waypoint_session;
      if (!ReadScan(r, w.scan)) break;
    }
    if (r.ok() && !map.nodes.emplace(node.id, std::move(node)).second) {
      return fail("node " + std::to_string(id) + " appears twice");
    }
    // Saved in id order; another order would change on the next save.
    if (r.ok() && map.nodes.rbegin()->first != id) {
      return fail("node " + std::to_string(id) + " is out of id order");
    }
  }
  std::uint64_t edge_count = 0;
  r.ReadCount(edge_count, 8 + 8 + 1 + 4 + 8 + 24 + 48, "edges");
  for (std::uint64_t n = 0; n < edge_count && r.ok(); ++n) {
    GraphEdge e;
    std::int64_t from = 0, to = 0;
    std::uint8_t kind = 0;
    std::int32_t session = 0;
    r.Read(from, "edge");
    r.Read(to, "edge");
    r.Read(kind, "edge kind");
    r.Read(session, "edge session");
    r.Read(e.stamp_s, "edge stamp");
    ReadPose(r, e.measurement, "edge measurement");
    ReadUpperTriangle(r, e.information, "edge information");
    // Before version 6 edges had one information only.
    std::uint8_t has_gating = 0;
    if (version >= 6 && r.Read(has_gating, "edge gating flag") && has_gating > 1) {
      return fail("invalid gating flag of edge " + std::to_string(n));
    }
    if (has_gating) {
      e.gating_information.emplace();
      ReadUpperTriangle(r, *e.gating_information, "edge gating information");
    }
    if (!r.ok()) break;
    if (!e.information.allFinite() ||
        (e.gating_information && !e.gating_information->allFinite())) {
      return fail("non-finite information of edge " + std::to_string(n));
    }
    if (kind > static_cast<std::uint8_t>(EdgeKind::kCondensed)) return fail("unknown edge kind");
    if (!map.nodes.count(from) || !map.nodes.count(to)) return fail("edge refers to a missing node");
    e.from = from;
    e.to = to;
    e.kind = static_cast<EdgeKind>(kind);
    e.session_id = session;
    map.edges.push_back(e);
  }
  std::uint64_t removed_count = 0;
  if (version >= 4) r.ReadCount(removed_count, 8 + 8 + 24, "removed nodes");
  for (std::uint64_t n = 0; n < removed_count && r.ok(); ++n) {
    std::int64_t id = 0, survivor = 0;
    RemovedNode removed;
    r.Read(id, "removed node");
    r.Read(survivor, "removed node survivor");
    ReadPose(r, removed.survivor_T_removed, "removed node pose");
    if (!r.ok()) break;
    if (map.nodes.count(id)) return fail("node " + std::to_string(id) + " is removed and present");
    if (!map.nodes.count(survivor)) {
      return fail("removed node " + std::to_string(id) + " refers to a missing node");
    }
    if (!map.removed_nodes.empty() && map.removed_nodes.rbegin()->first >= id) {
      return fail("removed node " + std::to_string(id) + " is out of id order");
    }
    removed.survivor = survivor;
    map.removed_nodes.emplace(id, removed);
  }
  if (!r.ok()) return fail(r.status().message());
  if (r.remaining() != 0) return fail("unexpected bytes after the removed nodes");
  if (!map.nodes.empty() && !map.nodes.count(map.gauge)) return fail("the gauge node is missing");
  if (version < 2 && !map.nodes.empty()) map.origin = map.nodes.begin()->second.map_T_node;
  return map;
}

Status SaveSessionMap(const SessionMap& map, const std::string& path) {
  return WriteFileAtomically(path, SerializeSessionMap(map));
}

StatusOr<SessionMap> LoadSessionMap(const std::string& path) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParseSessionMap(*bytes, path);
}

}  // namespace longterm_mapper2d
