#pragma once

#include <chrono>
#include <map>
#include <string>

namespace longterm_mapper2d {

// Accumulated wall time per named processing stage ("conversion", "registration", ...).
class StageTimes {
 public:
  void Add(const std::string& stage, double seconds) { seconds_[stage] += seconds; }
  const std::map<std::string, double>& seconds() const { return seconds_; }

 private:
  std::map<std::string, double> seconds_;
};

// Adds the time between construction and destruction to one stage.
class ScopedStageTimer {
 public:
  ScopedStageTimer(StageTimes& times, std::string stage)
      : times_(times), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedStageTimer() {
    times_.Add(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
                           .count());
  }
  ScopedStageTimer(const ScopedStageTimer&) = delete;
  ScopedStageTimer& operator=(const ScopedStageTimer&) = delete;

 private:
  StageTimes& times_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace longterm_mapper2d
