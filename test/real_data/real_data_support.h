#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "testing/temp_dir.h"

namespace longterm_mapper2d {
namespace test_support {

// The real-data tier runs only with LTM_REAL_DATA=1 (scripts/test.sh sets it under CI=true) and
// when the shared data folder exists; otherwise each test reports itself skipped with the reason.
inline std::string RealDataDirOrSkipReason(bool& available) {
  available = false;
  const char* enabled = std::getenv("LTM_REAL_DATA");
  if (!enabled || std::string(enabled) != "1") {
    return "skipped: real-data tier off (set LTM_REAL_DATA=1, or run scripts/test.sh with CI=true "
           "or --real-data)";
  }
  const char* override_dir = std::getenv("LTM_DATA_DIR");
  const std::string dir = override_dir ? override_dir : LTM_SHARED_DATA_DIR;
  if (FILE* f = std::fopen((dir + "/SOURCES.md").c_str(), "r")) {
    std::fclose(f);
    available = true;
    return dir;
  }
  return "skipped: no data folder at " + dir;
}

#define LTM_REQUIRE_REAL_DATA(dir_var)                                                \
  std::string dir_var;                                                                \
  {                                                                                   \
    bool available_ = false;                                                          \
    dir_var = ::longterm_mapper2d::test_support::RealDataDirOrSkipReason(available_); \
    if (!available_) GTEST_SKIP() << dir_var;                                         \
  }

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs a shell command, capturing its output.
inline CommandResult RunCommand(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe)) result.output += buffer;
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// offline_mapper's input option for a Freiburg log (intel, aces, fr079): its bag, or in the
// ROS-free build (LTM_CORE_ONLY, e.g. the sanitized CI stage) its CARMEN copy, which holds the
// same scans, stamps and odometry (SOURCES.md; RealDataIntel.BagAndCarmenLogGiveTheSame...).
inline std::string LogInput(const std::string& data, const std::string& name) {
#ifdef LTM_READS_BAGS
  return " --bag " + data + "/" + name + "/" + name + ".bag";
#else
  return " --carmen " + data + "/" + name + "/" + name + ".reconstructed.clf";
#endif
}

inline std::string Tool(const std::string& name) { return std::string(LTM_BIN_DIR) + "/" + name; }

// The value of "key": NUMBER in a JSON text, or NaN.
inline double JsonNumber(const std::string& json, const std::string& key) {
  const auto pos = json.find("\"" + key + "\":");
  if (pos == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + pos + key.size() + 3, nullptr);
}

// Relation errors of a trajectory (evaluate_relations' summary).
struct RelationErrors {
  double mean_m = 0.0;  // mean absolute translational error
  double max_m = 0.0;
  double rotation_deg = 0.0;  // mean absolute rotational error
};

// Maps a Freiburg log (intel, aces, fr079) with offline_mapper, `arguments` appended, writes the
// trajectory to `trajectory` and evaluates it against the log's relations.
inline RelationErrors MapAndEvaluate(const std::string& data, const std::string& name,
                                     const std::string& arguments, const std::string& trajectory) {
  const auto run = RunCommand(Tool("offline_mapper") + LogInput(data, name) + arguments +
                              " --trajectory " + trajectory);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const auto eval = RunCommand(Tool("evaluate_relations") + " --json --trajectory " + trajectory +
                               " --relations " + data + "/" + name + "/" + name + ".relations");
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
  return {JsonNumber(eval.output, "trans_abs_mean_m"), JsonNumber(eval.output, "trans_max_m"),
          JsonNumber(eval.output, "rot_abs_mean_deg")};
}

}  // namespace test_support
}  // namespace longterm_mapper2d
