#include "longterm_mapper2d/tools/scan_prefetcher.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace longterm_mapper2d {

Status ForEachPrefetched(RecordedScans& recording,
                         const std::function<void(const ScanInput&)>& visit, std::size_t capacity) {
  capacity = std::max<std::size_t>(capacity, 1);
  std::mutex mutex;
  std::condition_variable not_full, not_empty;
  std::deque<ScanInput> queue;
  bool done = false, abandoned = false;
  std::optional<Status> status;

  std::thread reader([&] {
    Status read = Status::Ok();
    try {
      read = recording.ForEach([&](const ScanInput& input) {
        std::unique_lock<std::mutex> lock(mutex);
        not_full.wait(lock, [&] { return queue.size() < capacity || abandoned; });
        if (abandoned) return;  // nobody takes scans any more: read on without keeping them
        queue.push_back(input);
        not_empty.notify_one();
      });
    } catch (const std::exception& e) {
      read = Status::Error(std::string("reading the recording failed: ") + e.what());
    }
    std::lock_guard<std::mutex> lock(mutex);
    status = read;
    done = true;
    not_empty.notify_one();
  });

  // Whatever happens on this side, the reader is released and joined.
  struct Joiner {
    std::thread& thread;
    std::mutex& mutex;
    std::condition_variable& not_full;
    bool& abandoned;
    ~Joiner() {
      {
        std::lock_guard<std::mutex> lock(mutex);
        abandoned = true;
      }
      not_full.notify_all();
      thread.join();
    }
  } joiner{reader, mutex, not_full, abandoned};

  while (true) {
    std::optional<ScanInput> next;
    {
      std::unique_lock<std::mutex> lock(mutex);
      not_empty.wait(lock, [&] { return !queue.empty() || done; });
      if (queue.empty()) break;  // done and drained
      next.emplace(std::move(queue.front()));
      queue.pop_front();
      not_full.notify_one();
    }
    visit(*next);
  }
  std::lock_guard<std::mutex> lock(mutex);
  return *status;
}

}  // namespace longterm_mapper2d
