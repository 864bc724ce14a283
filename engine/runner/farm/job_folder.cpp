#include "farm/job_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "loom/atomic_file.hpp"
#include "loom/error.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

namespace {
std::string number(int id) {
  char text[16];
  std::snprintf(text, sizeof text, "%04d", id);
  return text;
}

constexpr const char* kSubfolders[] = {"logs", "status", "slurm", "profiles"};

// One task of the manifest, every key checked, the problem named by its
// JSON pointer (an edited or damaged manifest must not crash or misrun).
Task parse_task(const json& t, std::size_t position, const std::string& file) {
  const std::string where = file + ": /tasks/" + std::to_string(position);
  if (!t.is_object()) throw Error(where + ": expected an object {\"id\", \"name\", \"stage\", \"args\"}");
  Task task;
  try {
    task.id = t.at("id").get<int>();
    task.name = t.at("name").get<std::string>();
    const int stage = t.at("stage").get<int>();
    if (stage < kSimulate || stage > kAssemble)
      throw Error(where + "/stage: " + std::to_string(stage) + " is not a stage (0: simulate, 1: work, 2: assemble)");
    task.stage = static_cast<Stage>(stage);
  } catch (const json::exception&) {
    throw Error(where + ": expected \"id\" and \"stage\" (integers) and \"name\" (a string)");
  }
  if (task.id != static_cast<int>(position))
    throw Error(where + "/id: task " + std::to_string(task.id) + " is listed at position " + std::to_string(position) +
                ": a task's id is its position in \"tasks\" (was the manifest edited?)");
  const json args = t.value("args", json());
  if (!args.is_array()) throw Error(where + "/args: task " + std::to_string(task.id) + " (" + task.name +
                                    ") has no \"args\" list (the loom arguments it runs)");
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (!args[k].is_string())
      throw Error(where + "/args/" + std::to_string(k) + ": task " + std::to_string(task.id) + " (" + task.name +
                  "): expected a string (a loom argument), got " + args[k].dump());
    task.args.push_back(args[k].get<std::string>());
  }
  const json wave = t.value("wave", json(0));
  if (!wave.is_number_integer() || wave.get<int>() < 0)
    throw Error(where + "/wave: task " + std::to_string(task.id) + " (" + task.name + "): expected 0 or more");
  task.wave = wave.get<int>();
  return task;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::string host_name() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

fs::path task_log(const fs::path& job, int id) { return job / "logs" / ("task-" + number(id) + ".log"); }
fs::path task_status_path(const fs::path& job, int id) { return job / "status" / (number(id) + ".json"); }

namespace {
void refuse_linked_subfolders(const fs::path& job) {
  for (const char* sub : kSubfolders) {
    std::error_code ec;
    if (fs::is_symlink(job / sub, ec))
      throw Error((job / sub).string() + " is a symbolic link: a job's logs, status and profiles stay inside "
                  "its folder (remove the link)");
  }
}
}  // namespace

void check_job_subfolders(const fs::path& job) {
  refuse_linked_subfolders(job);
  for (const char* sub : kSubfolders) {
    std::error_code ec;
    fs::create_directories(job / sub, ec);
    if (ec) throw Error("cannot make " + (job / sub).string() + ": " + ec.message());
  }
}

void save_manifest(const JobManifest& m) {
  json tasks = json::array();
  for (const Task& t : m.tasks)
    tasks.push_back({{"id", t.id}, {"name", t.name}, {"stage", static_cast<int>(t.stage)}, {"args", t.args}});
  for (std::size_t i = 0; i < m.tasks.size(); ++i) tasks[i]["wave"] = m.tasks[i].wave;
  const json doc = {{"loom_job", 1}, {"loom", m.loom},           {"to", m.to},
                    {"retries", m.retries}, {"jobs", m.jobs}, {"slurm_args", m.slurm_args},
                    {"tasks", tasks}};
  json written = doc;
  written["node_loom"] = m.node_loom;
  check_job_subfolders(m.dir);
  write_file_atomic(m.dir / "manifest.json", written.dump(2) + "\n");
}

JobManifest load_manifest(const fs::path& job) {
  const fs::path file = job / "manifest.json";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw Error(file.string() + ": cannot read (is " + job.string() + " a job folder written by loom submit?)");
  const json doc = json::parse(read_text(file), nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || doc.value("loom_job", 0) != 1 || !doc.contains("tasks") ||
      !doc["tasks"].is_array())
    throw Error(file.string() + ": not a loom job manifest (version 1)");
  JobManifest m;
  m.dir = fs::absolute(job);
  try {
    m.loom = doc.at("loom").get<std::string>();
    m.to = doc.at("to").get<std::string>();
    m.retries = doc.at("retries").get<int>();
    m.jobs = doc.at("jobs").get<int>();
    m.slurm_args = doc.at("slurm_args").get<std::vector<std::string>>();
    m.node_loom = doc.value("node_loom", "");
  } catch (const json::exception&) {
    throw Error(file.string() + ": expected \"loom\", \"to\" and \"node_loom\" (strings), \"retries\" and \"jobs\" "
                "(integers) and \"slurm_args\" (a list of strings)");
  }
  if (m.to != "local" && m.to != "slurm") throw Error(file.string() + ": /to: expected \"local\" or \"slurm\"");
  if (m.jobs < 1) throw Error(file.string() + ": /jobs: " + std::to_string(m.jobs) + " tasks at once runs nothing: "
                              "expected at least 1 (or give `loom jobs resume -j N`)");
  if (m.retries < 0) throw Error(file.string() + ": /retries: expected 0 or more, got " + std::to_string(m.retries));
  for (std::size_t k = 0; k < doc["tasks"].size(); ++k) m.tasks.push_back(parse_task(doc["tasks"][k], k, file.string()));
  refuse_linked_subfolders(m.dir);
  return m;
}

int open_task_log(const fs::path& job, int id) {
  const fs::path log = task_log(job, id);
  ::mkdir((job / "logs").c_str(), 0755);  // deleted by hand: made again
  const int dir = ::open((job / "logs").c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  int fd = dir < 0 ? -1 : ::openat(dir, log.filename().c_str(), O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0644);
  const int error = errno;
  if (dir >= 0) ::close(dir);
  if (fd < 0)
    throw Error("cannot open the task log " + log.string() + ": " + std::strerror(error) +
                (error == ELOOP || error == ENOTDIR ? " (a symbolic link: a job's logs are never written through one)"
                                                    : ""));
  return fd;
}

namespace {
void append_to(int fd, const fs::path& file, const std::string& line) {
  const std::string text = line + "\n";
  const ssize_t written = ::write(fd, text.data(), text.size());
  const int error = errno;
  ::close(fd);
  if (written != static_cast<ssize_t>(text.size())) throw Error("cannot write " + file.string() + ": " + std::strerror(error));
}
}  // namespace

void append_task_log(const fs::path& job, int id, const std::string& line) {
  append_to(open_task_log(job, id), task_log(job, id), line);
}

void append_line(const fs::path& file, const std::string& line) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw Error("cannot open " + file.string() + ": " + std::strerror(errno));
  append_to(fd, file, line);
}

namespace {
const fs::file_time_type g_started = fs::file_time_type::clock::now();
}  // namespace

fs::file_time_type process_started() { return g_started; }

unsigned long long process_start_time(long pid) {
  if (pid <= 0) return 0;
  const std::string stat = read_text("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t paren = stat.rfind(')');  // the command name may hold spaces and parentheses
  if (paren == std::string::npos) return 0;
  std::istringstream fields(stat.substr(paren + 1));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k)
    if (k == 22) return std::strtoull(field.c_str(), nullptr, 10);
  return 0;
}

bool same_process(long pid, unsigned long long start, const std::vector<std::string>& keywords) {
  const unsigned long long now = process_start_time(pid);
  if (now == 0) return false;
  if (start != 0) return now == start;
  std::string args = read_text("/proc/" + std::to_string(pid) + "/cmdline");
  std::vector<std::string> argv;
  for (std::size_t at = 0; at < args.size();) {
    const std::size_t end = std::min(args.find('\0', at), args.size());
    argv.push_back(args.substr(at, end - at));
    at = end + 1;
  }
  if (argv.empty() || fs::path(argv[0]).filename().string().find("loom") == std::string::npos) return false;
  for (const std::string& k : keywords)
    if (std::find(argv.begin(), argv.end(), k) == argv.end()) return false;
  return true;
}

JobLock::JobLock(const fs::path& job) {
  const fs::path path = job / "lock";
  // Not close-on-exec: the tasks started hold it too (see the header).
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW, 0644);
  if (fd_ < 0) throw Error("cannot open " + path.string() + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string holder = read_text(path);
    ::close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK) throw Error("cannot lock " + path.string() + ": " + std::strerror(error));
    throw Error("the tasks of " + job.string() + " are being run by another loom (pid " +
                holder.substr(0, holder.find('\n')) + ", or tasks it started): wait for it to end, or `loom jobs "
                "cancel " + job.string() + "`");
  }
  // The pid only serves the message of a refused second dispatcher.
  const std::string pid = std::to_string(::getpid()) + "\n";
  const bool noted = ::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) == static_cast<ssize_t>(pid.size());
  (void)noted;
}

JobLock::~JobLock() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {
constexpr std::pair<TaskState, const char*> kTaskStates[] = {{TaskState::pending, "pending"},
                                                             {TaskState::running, "running"},
                                                             {TaskState::done, "done"},
                                                             {TaskState::failed, "failed"},
                                                             {TaskState::cancelled, "cancelled"}};
}  // namespace

const char* task_state_text(TaskState state) {
  for (const auto& [s, text] : kTaskStates)
    if (s == state) return text;
  return "pending";
}

std::optional<TaskState> task_state_from_text(const std::string& text) {
  for (const auto& [s, word] : kTaskStates)
    if (text == word) return s;
  return std::nullopt;
}

TaskStatus read_status(const fs::path& job, int id) {
  TaskStatus s;
  std::error_code ec;
  if (!fs::is_regular_file(task_status_path(job, id), ec)) return s;
  const json doc = json::parse(read_text(task_status_path(job, id)), nullptr, false);
  if (!doc.is_object()) return s;
  try {
    s.state = task_state_from_text(doc.value("state", "pending")).value_or(TaskState::pending);
    s.exit = doc.value("exit", -1);
    s.attempts = doc.value("attempts", 0);
    s.seconds = doc.value("seconds", 0.0);
    s.host = doc.value("host", "");
    s.message = doc.value("message", "");
    s.pid = doc.value("pid", 0L);
    s.pid_start = doc.value("pid_start", 0ULL);
    s.loom = doc.value("loom", "");
    if (doc.contains("tries") && doc["tries"].is_array())
      for (const json& t : doc["tries"])
        if (t.is_object()) s.tries.push_back({t.value("host", ""), t.value("end", ""), t.value("seconds", 0.0)});
  } catch (const json::exception&) {
    return TaskStatus{};  // a damaged status file: the task has not run as far as anyone can tell
  }
  return s;
}

void write_status(const fs::path& job, int id, const TaskStatus& s) {
  const json doc = {{"state", task_state_text(s.state)},
                    {"exit", s.exit},
                    {"attempts", s.attempts},
                    {"seconds", s.seconds},
                    {"host", s.host},
                    {"message", s.message},
                    {"pid", s.pid},
                    {"pid_start", s.pid_start}};
  json written = doc;
  written["loom"] = s.loom;
  written["tries"] = json::array();
  for (const TaskTry& t : s.tries)
    written["tries"].push_back({{"host", t.host}, {"end", t.end}, {"seconds", t.seconds}});
  write_file_atomic(task_status_path(job, id), written.dump(2) + "\n");
}

}  // namespace loom::runner
