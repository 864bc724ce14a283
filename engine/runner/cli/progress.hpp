// What `loom run` shows while it works: on a terminal, a progress bar for each
// node that runs longer than a moment; otherwise (a log file, a pipe) plain
// lines: a node's 25% steps, or over a frame range one line per frame and
// nothing within a frame. Warnings always, each once per node however many
// frames repeat it; node log lines unless --quiet. Over a frame range,
// "frame k of N" above the bars.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <set>
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
  bool sequence_ = false;   // a range of more than one frame is running
  std::set<std::string> warned_;  // "id\ntext" of each warning printed
  int repeated_warnings_ = 0;
  int drawn_lines_ = 0;
  bool stopping_ = false;
  std::thread painter_;
};

// "frame 12 (3 of 60)", or "frame 3 of 60" when the frame is the index.
std::string frame_text(int frame, int index, int count);

}  // namespace loom::runner
