#include "longterm_mapper2d/core/map/session_map_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <limits>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/binary_io.h"
#include "testing/temp_dir.h"

namespace longterm_mapper2d {
namespace {

SessionMap SmallMap() {
  SessionMap map;
  map.sessions = 2;
  map.gauge = 3;
  for (NodeId id : {3, 4, 7}) {
    LocalMapNode node;
    node.id = id;
    node.session_id = id == 7 ? 1 : 0;
    node.stamp_s = 100.0 + id;
    node.map_T_node = Pose2(0.5 * id, -0.25 * id, 0.1 * id);
    for (int k = 0; k < 5; ++k) {
      RichPoint p;
      p.point_m = Eigen::Vector2d(k, 0.3 * k);
      p.normal = Eigen::Vector2d(0.6, 0.8);
      p.weight = 1.0 / (k + 1);
      p.inherited = id == 7 && k >= 3;  // merged in from an older node
      node.cloud.push_back(p);
    }
    Waypoint w;
    w.node_T_base = Pose2(-0.1, 0.0, 0.01);
    w.base_T_laser = Pose2(0.22, 0.0, 0.0);
    w.scan.stamp_s = 99.5 + id;
    w.scan.frame_id = "laser";
    w.scan.angle_min_rad = -M_PI / 2;
    w.scan.angle_increment_rad = M_PI / 180;
    w.scan.range_min_m = 0.1;
    w.scan.range_max_m = 30.0;
    w.scan.ranges = {1.0f, 2.5f, std::numeric_limits<float>::infinity(), 3.0f};
    w.session_id = node.session_id;
    node.waypoints.push_back(w);
    if (id == 7) {
      w.session_id = 0;  // merged in from an older session
      node.waypoints.push_back(w);
    }
    map.nodes.emplace(id, node);
  }
  GraphEdge odometry;
  odometry.from = 3;
  odometry.to = 4;
  odometry.measurement = Pose2(0.5, -0.25, 0.1);
  odometry.information << 100, 1, 2, 1, 90, 3, 2, 3, 400;
  odometry.gating_information = 0.01 * odometry.information;
  map.edges.push_back(odometry);
  GraphEdge closure = odometry;
  closure.gating_information.reset();
  closure.from = 7;
  closure.to = 3;
  closure.kind = EdgeKind::kLoopClosure;
  closure.session_id = 1;
  map.edges.push_back(closure);
  map.removed_nodes[5] = RemovedNode{7, Pose2(0.1, 0.2, 0.3)};
  return map;
}

TEST(SessionMapFile, RoundTripIsByteIdentical) {
  const std::string bytes = SerializeSessionMap(SmallMap());
  const auto parsed = ParseSessionMap(bytes, "small.ltmap");
  ASSERT_TRUE(parsed.ok()) << parsed.status().message();
  EXPECT_EQ(parsed->nodes.size(), 3u);
  EXPECT_EQ(parsed->edges.size(), 2u);
  EXPECT_EQ(parsed->edges[1].kind, EdgeKind::kLoopClosure);
  ASSERT_TRUE(parsed->edges[0].gating_information.has_value());
  EXPECT_EQ(*parsed->edges[0].gating_information, 0.01 * parsed->edges[0].information);
  EXPECT_FALSE(parsed->edges[1].gating_information.has_value());
  EXPECT_EQ(parsed->nodes.at(7).session_id, 1);
  EXPECT_FALSE(parsed->nodes.at(7).cloud[2].inherited);
  EXPECT_TRUE(parsed->nodes.at(7).cloud[3].inherited);
  EXPECT_FALSE(parsed->nodes.at(4).cloud[3].inherited);
  EXPECT_EQ(parsed->nodes.at(4).waypoints[0].scan.ranges.size(), 4u);
  ASSERT_EQ(parsed->nodes.at(7).waypoints.size(), 2u);
  EXPECT_EQ(parsed->nodes.at(7).waypoints[0].session_id, 1);
  EXPECT_EQ(parsed->nodes.at(7).waypoints[1].session_id, 0);
  ASSERT_EQ(parsed->removed_nodes.size(), 1u);
  EXPECT_EQ(parsed->removed_nodes.at(5).survivor, 7);
  EXPECT_NEAR(parsed->removed_nodes.at(5).survivor_T_removed.theta(), 0.3, 1e-12);
  EXPECT_EQ(SerializeSessionMap(*parsed), bytes);
}

TEST(SessionMapFile, RemovedNodesMustPointAtNodesOfTheMap) {
  SessionMap map = SmallMap();
  map.removed_nodes[6] = RemovedNode{8, Pose2()};  // node 8 does not exist
  auto parsed = ParseSessionMap(SerializeSessionMap(map), "dangling.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("refers to a missing node"), std::string::npos);
  map = SmallMap();
  map.removed_nodes[4] = RemovedNode{7, Pose2()};  // node 4 is still in the map
  parsed = ParseSessionMap(SerializeSessionMap(map), "both.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("removed and present"), std::string::npos);
}

TEST(SessionMapFile, EveryTruncationIsRefusedWithAReason) {
  const std::string bytes = SerializeSessionMap(SmallMap());
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    const auto parsed = ParseSessionMap(bytes.substr(0, length), "cut.ltmap");
    ASSERT_FALSE(parsed.ok()) << "accepted a file cut at byte " << length;
    EXPECT_NE(parsed.status().message().find("cut.ltmap"), std::string::npos);
  }
}

TEST(SessionMapFile, CorruptionAndNewerVersionsAreRefused) {
  const std::string bytes = SerializeSessionMap(SmallMap());
  for (std::size_t at = 0; at < bytes.size(); at += 7) {
    std::string corrupt = bytes;
    corrupt[at] = static_cast<char>(corrupt[at] ^ 0x5A);
    EXPECT_FALSE(ParseSessionMap(corrupt, "bad.ltmap").ok()) << "byte " << at;
  }
  std::string newer = bytes;
  newer[8] = static_cast<char>(kSessionMapVersion + 1);  // version field
  const auto parsed = ParseSessionMap(newer, "new.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("newer"), std::string::npos);
}

// A file of the given format version around a hand-made payload, with a valid size and checksum.
std::string FileWith(std::uint32_t version, const std::string& body) {
  BinaryWriter file;
  file.WriteBytes("LTMAP2D\n");
  file.Write<std::uint32_t>(version);
  file.Write<std::uint64_t>(body.size());
  file.Write<std::uint32_t>(Crc32(body.data(), body.size()));
  file.WriteBytes(body);
  return file.bytes();
}

TEST(SessionMapFile, AnAbsurdNodeCountDoesNotAllocate) {
  // A valid header and checksum over a payload that claims 10^9 nodes.
  BinaryWriter payload;
  payload.Write<std::int32_t>(1);
  payload.Write<std::int64_t>(0);
  payload.Write<std::uint64_t>(1000000000ull);
  const auto parsed = ParseSessionMap(FileWith(1, payload.bytes()), "huge.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("implausible count"), std::string::npos);
}

// A one-node map with one waypoint, and its payload in the layout of an older format version:
// version 4 lacks the points' flags (a byte after each point's five doubles), version 3 also the
// removed nodes (their count of 0 ends the payload), version 2 also the waypoint's session (4
// bytes after its two poses), version 1 also the origin.
SessionMap OneNodeMap() {
  SessionMap map = SmallMap();
  map.nodes.erase(4);
  map.nodes.erase(7);
  map.edges.clear();
  map.removed_nodes.clear();
  map.origin = Pose2(7.0, 8.0, 0.5);
  map.nodes.at(3).session_id = 1;
  map.nodes.at(3).waypoints[0].session_id = 0;
  return map;
}

std::string OlderPayload(const SessionMap& map, std::uint32_t version) {
  const std::string current = SerializeSessionMap(map);
  constexpr std::size_t kHeader = 24, kOriginAt = kHeader + 4 + 8;
  const std::size_t node_at = kOriginAt + 24 + 8;
  const std::size_t points = map.nodes.begin()->second.cloud.size();
  const std::size_t points_at = node_at + 8 + 4 + 8 + 24 + 8;
  const std::size_t waypoint_session_at = points_at + 40 * points + 8 + 48;  // without flags
  std::string body = current.substr(kHeader, current.size() - kHeader - (version <= 3 ? 8 : 0));
  if (version <= 4) {
    for (std::size_t k = points; k-- > 0;) body.erase(points_at + 41 * k + 40 - kHeader, 1);
  }
  if (version <= 2) body.erase(waypoint_session_at - kHeader, 4);
  if (version == 1) body.erase(kOriginAt - kHeader, 24);
  return body;
}

TEST(SessionMapFile, VersionOneFilesLoadWithTheFirstNodeAsOrigin) {
  const SessionMap map = OneNodeMap();
  const auto parsed = ParseSessionMap(FileWith(1, OlderPayload(map, 1)), "old.ltmap");
  ASSERT_TRUE(parsed.ok()) << parsed.status().message();
  EXPECT_EQ(parsed->nodes.size(), map.nodes.size());
  EXPECT_NEAR(parsed->origin.x(), map.nodes.begin()->second.map_T_node.x(), 1e-12);
  EXPECT_NEAR(parsed->origin.y(), map.nodes.begin()->second.map_T_node.y(), 1e-12);
  // Version 2 keeps its own origin.
  const auto v2 = ParseSessionMap(FileWith(2, OlderPayload(map, 2)), "v2.ltmap");
  ASSERT_TRUE(v2.ok()) << v2.status().message();
  EXPECT_NEAR(v2->origin.x(), 7.0, 1e-12);
}

TEST(SessionMapFile, WaypointsOfOlderVersionsTakeTheSessionOfTheirNode) {
  const SessionMap map = OneNodeMap();
  const auto v2 = ParseSessionMap(FileWith(2, OlderPayload(map, 2)), "v2.ltmap");
  ASSERT_TRUE(v2.ok()) << v2.status().message();
  const Waypoint& w = v2->nodes.at(3).waypoints.at(0);
  EXPECT_EQ(w.session_id, 1);
  EXPECT_EQ(w.scan.ranges.size(), 4u);
  EXPECT_NEAR(w.base_T_laser.x(), 0.22, 1e-12);
  // Saved again, it is a current-version file that differs from the original only in that
  // session.
  SessionMap expected = map;
  expected.nodes.at(3).waypoints[0].session_id = 1;
  EXPECT_EQ(SerializeSessionMap(*v2), SerializeSessionMap(expected));
}

TEST(SessionMapFile, VersionThreeFilesLoadWithoutRemovedNodes) {
  const SessionMap map = OneNodeMap();
  const auto v3 = ParseSessionMap(FileWith(3, OlderPayload(map, 3)), "v3.ltmap");
  ASSERT_TRUE(v3.ok()) << v3.status().message();
  EXPECT_TRUE(v3->removed_nodes.empty());
  EXPECT_EQ(v3->nodes.at(3).waypoints.at(0).session_id, 0);
  EXPECT_EQ(SerializeSessionMap(*v3), SerializeSessionMap(map));
}

TEST(SessionMapFile, PointsOfVersionFourFilesAreAllTheirNodesOwn) {
  SessionMap map = OneNodeMap();
  for (RichPoint& p : map.nodes.at(3).cloud) p.inherited = true;  // no flags in version 4
  const auto v4 = ParseSessionMap(FileWith(4, OlderPayload(map, 4)), "v4.ltmap");
  ASSERT_TRUE(v4.ok()) << v4.status().message();
  ASSERT_EQ(v4->nodes.at(3).cloud.size(), map.nodes.at(3).cloud.size());
  for (const RichPoint& p : v4->nodes.at(3).cloud) EXPECT_FALSE(p.inherited);
  EXPECT_NEAR(v4->nodes.at(3).cloud[4].weight, 0.2, 1e-12);
  EXPECT_EQ(v4->nodes.at(3).waypoints.at(0).session_id, 0);
}

// SmallMap's payload without the edges' gating flags (version 5): its edges have no gating
// information. Each edge is 102 bytes in version 6, its flag last; 48 bytes of removed nodes end
// the payload.
TEST(SessionMapFile, EdgesOfVersionFiveFilesHaveOneInformation) {
  SessionMap map = SmallMap();
  for (GraphEdge& e : map.edges) e.gating_information.reset();
  constexpr std::size_t kHeader = 24, kEdgeBytes = 102, kRemovedBytes = 48;
  std::string body = SerializeSessionMap(map).substr(kHeader);
  const std::size_t edges_end = body.size() - kRemovedBytes;
  for (std::size_t k = 0; k < map.edges.size(); ++k) {
    const std::size_t flag = edges_end - k * kEdgeBytes - 1;
    ASSERT_EQ(body[flag], 0);
    body.erase(flag, 1);
  }
  const auto v5 = ParseSessionMap(FileWith(5, body), "v5.ltmap");
  ASSERT_TRUE(v5.ok()) << v5.status().message();
  ASSERT_EQ(v5->edges.size(), 2u);
  for (const GraphEdge& e : v5->edges) EXPECT_FALSE(e.gating_information.has_value());
  EXPECT_EQ(v5->edges[0].information, map.edges[0].information);
  EXPECT_EQ(SerializeSessionMap(*v5), SerializeSessionMap(map));
}

TEST(SessionMapFile, AnInvalidGatingFlagIsRefused) {
  SessionMap map = SmallMap();
  map.edges[0].gating_information.reset();
  constexpr std::size_t kHeader = 24, kEdgeBytes = 102, kRemovedBytes = 48;
  std::string body = SerializeSessionMap(map).substr(kHeader);
  const std::size_t first_flag = body.size() - kRemovedBytes - 2 * kEdgeBytes + kEdgeBytes - 1;
  ASSERT_EQ(body[first_flag], 0);
  body[first_flag] = 2;
  const auto parsed = ParseSessionMap(FileWith(kSessionMapVersion, body), "gating.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("invalid gating flag"), std::string::npos)
      << parsed.status().message();
}

TEST(SessionMapFile, UnknownPointFlagsAreRefused) {
  const SessionMap map = OneNodeMap();
  constexpr std::size_t kHeader = 24;
  std::string body = SerializeSessionMap(map).substr(kHeader);
  const std::size_t first_flags = 4 + 8 + 24 + 8 + 8 + 4 + 8 + 24 + 8 + 40;
  ASSERT_EQ(body[first_flags], 0);
  body[first_flags] = 2;
  const auto parsed = ParseSessionMap(FileWith(kSessionMapVersion, body), "flags.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("unknown cloud point flags"), std::string::npos)
      << parsed.status().message();
}

TEST(SessionMapFile, AFailedSaveKeepsThePreviousFile) {
  const test_support::ScopedTempDir temp("ltmap_test");
  const std::string& dir = temp.path();
  const std::string path = dir + "/map.ltmap";
  ASSERT_TRUE(SaveSessionMap(SmallMap(), path).ok());
  const auto before = ReadFileBytes(path);
  ASSERT_TRUE(before.ok());
  // Saving into a folder that does not exist fails and leaves the old file alone.
  EXPECT_FALSE(SaveSessionMap(SmallMap(), dir + "/missing/map.ltmap").ok());
  const auto loaded = LoadSessionMap(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  EXPECT_EQ(SerializeSessionMap(*loaded), *before);
  EXPECT_FALSE(LoadSessionMap(dir + "/none.ltmap").ok());
}

// Found by test/fuzz/ltmap_fuzzer: files with a pose angle outside (-pi, pi] or with nodes out of
// id order loaded (the angle normalised, the nodes sorted), so saving the loaded map changed the
// bytes. No writer produces them; they are refused like any other corruption.
TEST(SessionMapFile, UnnormalisedAnglesAndUnsortedNodesAreRefused) {
  const std::string angle(
      "LTMAP2D\n"
      "\x02\x00\x00\x00"                   // version 2
      "\x34\x00\x00\x00\x00\x00\x00\x00"   // payload size
      "\x51\xca\x02\xd6"                   // CRC-32
      "\x01\x00\x00\x00"                   // sessions
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // gauge
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // origin x
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // origin y
      "\x00\x00\x00\x00\x00\x00\x10\x40"   // origin theta = 4.0
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // no nodes
      "\x00\x00\x00\x00\x00\x00\x00\x00",  // no edges
      76);
  auto parsed = ParseSessionMap(angle, "angle.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("angle outside (-pi, pi] in origin"), std::string::npos)
      << parsed.status().message();

  const std::string header(
      "LTMAP2D\n"
      "\x02\x00\x00\x00"                   // version 2
      "\xac\x00\x00\x00\x00\x00\x00\x00"   // payload size
      "\x82\x85\x16\x0b"                   // CRC-32
      "\x01\x00\x00\x00"                   // sessions
      "\x01\x00\x00\x00\x00\x00\x00\x00"   // gauge
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // origin x
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // origin y
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // origin theta
      "\x02\x00\x00\x00\x00\x00\x00\x00",  // two nodes
      68);
  const std::string node_2(
      "\x02\x00\x00\x00\x00\x00\x00\x00"   // id 2
      "\x00\x00\x00\x00"                   // session
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // stamp
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // x
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // y
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // theta
      "\x00\x00\x00\x00\x00\x00\x00\x00"   // no points
      "\x00\x00\x00\x00\x00\x00\x00\x00",  // no waypoints
      60);
  std::string node_1 = node_2;
  node_1[0] = '\x01';
  const std::string order = header + node_2 + node_1 + std::string(8, '\0');  // no edges
  ASSERT_EQ(order.size(), 196u);
  parsed = ParseSessionMap(order, "order.ltmap");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("node 1 is out of id order"), std::string::npos)
      << parsed.status().message();
}

}  // namespace
}  // namespace longterm_mapper2d
