#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace longterm_mapper2d {

// A progress bar on stderr (percent, scans/s, ETA) when stderr is a terminal; silent otherwise
// (the caller prints a one-line summary at the end).
class ProgressReporter {
 public:
  explicit ProgressReporter(std::uint64_t total);
  void Update(std::uint64_t done);
  void Finish();
  double elapsed_s() const;

 private:
  std::uint64_t total_;
  bool interactive_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace longterm_mapper2d
