#include "cli/watch.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include "cli/exit_codes.hpp"
#include "loom/graph.hpp"
#include "loom/graph_view.hpp"
#include "loom/input_file.hpp"
#include "loom/plugin_loader.hpp"

namespace loom::runner {

namespace fs = std::filesystem;

std::vector<fs::path> files_read(const fs::path& graph_file) {
  std::vector<fs::path> files{fs::absolute(graph_file).lexically_normal()};
  try {
    const Graph graph = load_graph_file(graph_file);
    Registry registry;
    PluginLoader loader(registry);
    loader.load_for(node_types_used(graph));
    for (const fs::path& f : GraphView(graph, registry).files())
      if (f != files.front()) files.push_back(f);
  } catch (const std::exception&) {
    // The run reports what is wrong with the graph; watching it is enough.
  }
  return files;
}

namespace {

// inotify watches on the folders of a set of files: an editor may replace a
// file by renaming another onto it, which a watch on the file itself misses.
class FolderWatch {
 public:
  explicit FolderWatch(const std::vector<fs::path>& files) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    if (fd_ < 0) {
      problem_ = std::string("inotify: ") + std::strerror(errno);
      return;
    }
    for (const fs::path& f : files) {
      files_.insert(f);
      const int wd = ::inotify_add_watch(fd_, f.parent_path().c_str(),
                                         IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE | IN_DELETE);
      if (wd >= 0) folders_[wd] = f.parent_path();
      else std::fprintf(stderr, "warning: cannot watch %s: %s\n", f.parent_path().c_str(), std::strerror(errno));
    }
  }
  ~FolderWatch() {
    if (fd_ >= 0) ::close(fd_);
  }
  FolderWatch(const FolderWatch&) = delete;
  FolderWatch& operator=(const FolderWatch&) = delete;

  // Why nothing can be watched, or "".
  const std::string& problem() const { return problem_; }

  // The watched files that changed, once changes have been quiet for a moment
  // (a save is often several events); empty when `cancel` was set first.
  std::set<fs::path> wait(const std::atomic<bool>& cancel) {
    std::set<fs::path> changed;
    constexpr int kQuietMs = 150, kCheckCancelMs = 100;
    while (!cancel.load()) {
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, changed.empty() ? kCheckCancelMs : kQuietMs);
      if (ready > 0) read_events(changed);
      else if (ready == 0 && !changed.empty()) return changed;
    }
    return {};
  }

 private:
  void read_events(std::set<fs::path>& changed) {
    alignas(inotify_event) char buffer[16384];
    ssize_t n;
    while ((n = ::read(fd_, buffer, sizeof buffer)) > 0) {
      for (char* at = buffer; at < buffer + n;) {
        const auto* event = reinterpret_cast<const inotify_event*>(at);
        at += sizeof(inotify_event) + event->len;
        auto folder = folders_.find(event->wd);
        if (folder == folders_.end() || event->len == 0) continue;
        const fs::path file = folder->second / event->name;
        if (files_.count(file)) changed.insert(file);
      }
    }
  }

  int fd_;
  std::string problem_;
  std::map<int, fs::path> folders_;
  std::set<fs::path> files_;
};


std::string names(const std::set<fs::path>& files) {
  std::string text;
  for (const fs::path& f : files) {
    const fs::path rel = f.lexically_relative(fs::current_path());
    text += (text.empty() ? "" : ", ") + (rel.empty() || *rel.begin() == ".." ? f : rel).string();
  }
  return text;
}

}  // namespace

int watch(const fs::path& graph_file, const std::atomic<bool>& cancel, const std::function<int()>& run_once) {
  for (;;) {
    // A FIFO or a device cannot be watched for saves, and opening one blocks
    // (a FIFO until a writer comes) where Ctrl-C only sets the cancel flag.
    if (const std::string kind = not_a_regular_file(graph_file); !kind.empty()) {
      std::fprintf(stderr, "error: --watch: %s is %s, not a file: --watch follows a graph file as it is saved\n",
                   graph_file.c_str(), kind.c_str());
      return kInvalid;
    }
    // Watched from before the run, so a save during the run is not missed;
    // listed again each time, as the graph may name other files now.
    const std::vector<fs::path> files = files_read(graph_file);
    if (cancel.load()) return kInterrupted;
    FolderWatch watch(files);
    const int code = run_once();
    if (cancel.load()) return code;
    if (!watch.problem().empty()) {
      std::fprintf(stderr, "error: --watch: %s\n", watch.problem().c_str());
      return kInvalid;
    }
    std::fprintf(stderr, "watching %zu file%s for changes (Ctrl-C to stop)\n", files.size(),
                 files.size() == 1 ? "" : "s");
    const std::set<fs::path> changed = watch.wait(cancel);
    if (changed.empty()) return kOk;
    std::fprintf(stderr, "changed: %s: running again\n", names(changed).c_str());
  }
}

}  // namespace loom::runner
