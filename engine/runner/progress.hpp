// What `loom run` shows while it works: on a terminal, a progress bar for each
// node that runs longer than a moment; otherwise plain lines at 25% steps.
// Warnings always; node log lines unless --quiet. Over a frame range, "frame
// k of N" above the bars (or a line at every tenth of the range).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "loom/evaluator.hpp"

namespace loom::runner {

class ConsoleObserver final : public Observer {
 public:
  explicit ConsoleObserver(bool quiet);
  ~ConsoleObserver() override;
  void stop();  // clears the bars; call before printing the summary

  void node_started(const std::string& id, const std::string& type) override;
  void node_progress(const std::string& id, double fraction, const std::string& label) override;
  void node_message(const std::string& id, bool warning, const std::string& text) override;
  void node_finished(const std::string& id, const NodeReport& report) override;
  void frame_started(int frame, int index, int count) override;

 private:
  struct Active {
    std::string type, label;
    double fraction = 0;
    int printed_quarter = 0;
    std::chrono::steady_clock::time_point start;
  };
  void draw_locked();
  void clear_locked();
  void print_locked(const std::string& line);

  const bool quiet_;
  const bool tty_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, Active> active_;
  std::string frame_line_;  // "frame k of N" while a frame range runs
  int drawn_lines_ = 0;
  bool stopping_ = false;
  std::thread painter_;
};

}  // namespace loom::runner
