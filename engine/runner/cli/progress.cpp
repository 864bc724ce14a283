#include "cli/progress.hpp"

#include <cstdio>

#include <unistd.h>

namespace loom::runner {

namespace {
constexpr auto kShowAfter = std::chrono::milliseconds(300);
constexpr auto kRedraw = std::chrono::milliseconds(100);
}  // namespace

ConsoleObserver::ConsoleObserver(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0) {
  if (tty_ && !quiet_)
    painter_ = std::thread([this] {
      std::unique_lock lock(mutex_);
      while (!stopping_) {
        wake_.wait_for(lock, kRedraw);
        if (!stopping_) draw_locked();
      }
    });
}

ConsoleObserver::~ConsoleObserver() { stop(); }

void ConsoleObserver::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
    clear_locked();
    if (repeated_warnings_ > 0)
      std::fprintf(stderr, "(%d repeated warnings not shown again: the profile lists each once)\n",
                   repeated_warnings_);
  }
  wake_.notify_all();
  if (painter_.joinable()) painter_.join();
}

void ConsoleObserver::clear_locked() {
  for (int i = 0; i < drawn_lines_; ++i) std::fputs("\x1b[1A\x1b[2K", stderr);
  drawn_lines_ = 0;
}

void ConsoleObserver::draw_locked() {
  clear_locked();
  auto now = std::chrono::steady_clock::now();
  if (!frame_line_.empty()) {
    std::fprintf(stderr, "%s\n", frame_line_.c_str());
    ++drawn_lines_;
  }
  for (const auto& [id, a] : active_) {
    if (now - a.start < kShowAfter) continue;
    constexpr int width = 30;
    int filled = static_cast<int>(a.fraction * width);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(width - filled), '.');
    double secs = std::chrono::duration<double>(now - a.start).count();
    std::fprintf(stderr, "%-16.16s [%s] %3d%% %6.1fs %s\n", id.c_str(), bar.c_str(),
                 static_cast<int>(a.fraction * 100), secs, a.label.c_str());
    ++drawn_lines_;
  }
  std::fflush(stderr);
}

void ConsoleObserver::print_locked(const std::string& line) {
  clear_locked();
  std::fprintf(stderr, "%s\n", line.c_str());
}

void ConsoleObserver::node_started(const std::string& id, const std::string& type) {
  std::lock_guard lock(mutex_);
  active_[id] = Active{type, "", 0, 0, std::chrono::steady_clock::now()};
}

void ConsoleObserver::node_progress(const std::string& id, double fraction, const std::string& label) {
  std::lock_guard lock(mutex_);
  auto it = active_.find(id);
  if (it == active_.end()) return;
  it->second.fraction = fraction;
  it->second.label = label;
  if (tty_ || quiet_ || sequence_) return;  // in a sequence: the frame lines only
  int quarter = static_cast<int>(fraction * 4);
  if (quarter > it->second.printed_quarter && fraction < 1.0) {
    it->second.printed_quarter = quarter;
    print_locked("[" + id + "] " + std::to_string(quarter * 25) + "%" +
                 (label.empty() ? "" : " " + label));
  }
}

void ConsoleObserver::node_message(const std::string& id, bool warning, const std::string& text) {
  std::lock_guard lock(mutex_);
  if (warning) {
    // A frame range repeats a node's warning at every frame: once is enough.
    if (warned_.insert(id + '\n' + text).second) print_locked("warning: [" + id + "] " + text);
    else ++repeated_warnings_;
  } else if (!quiet_) {
    print_locked("[" + id + "] " + text);
  }
}

void ConsoleObserver::node_finished(const std::string& id, const NodeReport& report) {
  std::lock_guard lock(mutex_);
  auto it = active_.find(id);
  if (it == active_.end()) return;
  bool long_run = std::chrono::steady_clock::now() - it->second.start >= kShowAfter;
  active_.erase(it);
  if (!quiet_ && !sequence_ && long_run && report.status == NodeStatus::ran) {
    char line[128];
    std::snprintf(line, sizeof line, "[%s] done in %.2f s", id.c_str(), report.seconds);
    print_locked(line);
  }
}

void ConsoleObserver::frame_started(int frame, int index, int count) {
  std::lock_guard lock(mutex_);
  sequence_ = count > 1;
  frame_line_ = frame_text(frame, index, count);
  if (!tty_ && !quiet_) print_locked(frame_line_);
}

std::string frame_text(int frame, int index, int count) {
  const std::string of = std::to_string(index) + " of " + std::to_string(count);
  return frame == index ? "frame " + of : "frame " + std::to_string(frame) + " (" + of + ")";
}

}  // namespace loom::runner
