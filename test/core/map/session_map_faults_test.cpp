// Faults while saving a session map: a full file system and a process killed mid-save must leave
// the previous file intact and loadable.
#include <gtest/gtest.h>
#include <dirent.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "testing/temp_dir.h"

namespace longterm_mapper2d {
namespace {

// A map of `nodes` nodes with `points` points each; `tag` makes maps of equal size differ.
SessionMap MapOfSize(int nodes, int points, double tag) {
  SessionMap map;
  map.sessions = 1;
  for (int id = 0; id < nodes; ++id) {
    LocalMapNode node;
    node.id = id;
    node.map_T_node = Pose2(id, tag, 0.0);
    for (int k = 0; k < points; ++k) {
      RichPoint p;
      p.point_m = Eigen::Vector2d(0.01 * k, tag);
      p.normal = Eigen::Vector2d(0.0, 1.0);
      node.cloud.push_back(p);
    }
    map.nodes.emplace(id, std::move(node));
  }
  return map;
}

int FilesIn(const std::string& dir) {
  int count = 0;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (dirent* e = ::readdir(d)) count += e->d_name[0] != '.';
    ::closedir(d);
  }
  return count;
}

TEST(SessionMapFaults, AFullFileSystemKeepsThePreviousFile) {
  const test_support::ScopedTempDir temp("ltmap_faults");
  const std::string& dir = temp.path();
  const std::string path = dir + "/map.ltmap";
  ASSERT_TRUE(SaveSessionMap(MapOfSize(2, 100, 0.0), path).ok());
  const auto before = ReadFileBytes(path);
  ASSERT_TRUE(before.ok());
  // The file-size limit stands in for a full disk: writes past it fail (EFBIG) as on ENOSPC.
  ::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit limited = old;
  limited.rlim_cur = before->size() + 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  const Status saved = SaveSessionMap(MapOfSize(50, 2000, 1.0), path);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
  EXPECT_FALSE(saved.ok());
  EXPECT_NE(saved.message().find("map.ltmap"), std::string::npos) << saved.message();
  const auto after = ReadFileBytes(path);
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(*after, *before);
  EXPECT_TRUE(LoadSessionMap(path).ok());
  EXPECT_EQ(FilesIn(dir), 1) << "the temporary file was left behind";
}

TEST(SessionMapFaults, KillingTheProcessDuringASaveKeepsAWholeFile) {
  const test_support::ScopedTempDir temp("ltmap_faults");
  const std::string& dir = temp.path();
  const std::string path = dir + "/map.ltmap";
  const SessionMap a = MapOfSize(40, 3000, 1.0), b = MapOfSize(40, 3000, 2.0);
  const std::string bytes_a = SerializeSessionMap(a), bytes_b = SerializeSessionMap(b);
  ASSERT_TRUE(SaveSessionMap(a, path).ok());
  for (int round = 0; round < 8; ++round) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      for (int i = 0;; ++i) SaveSessionMap(i % 2 ? a : b, path);  // until killed
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20 + 37 * round));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    const auto loaded = ReadFileBytes(path);
    ASSERT_TRUE(loaded.ok());
    EXPECT_TRUE(*loaded == bytes_a || *loaded == bytes_b) << "round " << round;
    EXPECT_TRUE(LoadSessionMap(path).ok()) << "round " << round;
  }
}

}  // namespace
}  // namespace longterm_mapper2d
