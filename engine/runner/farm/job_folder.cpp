#include "farm/job_folder.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>

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
}  // namespace

std::string host_name() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

fs::path task_log(const fs::path& job, int id) { return job / "logs" / ("task-" + number(id) + ".log"); }
fs::path task_status_path(const fs::path& job, int id) { return job / "status" / (number(id) + ".json"); }

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
  for (const char* sub : {"logs", "status", "slurm", "profiles"}) fs::create_directories(m.dir / sub);
  write_file_atomic(m.dir / "manifest.json", written.dump(2) + "\n");
}

JobManifest load_manifest(const fs::path& job) {
  const fs::path file = job / "manifest.json";
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot read (is " + job.string() + " a job folder written by loom submit?)");
  const json doc = json::parse(in, nullptr, false);
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
    for (const json& t : doc["tasks"])
      m.tasks.push_back({t.at("id").get<int>(), t.at("name").get<std::string>(),
                         static_cast<Stage>(t.at("stage").get<int>()), t.at("args").get<std::vector<std::string>>(),
                         t.value("wave", 0)});
  } catch (const json::exception& e) {
    throw Error(file.string() + ": " + e.what());
  }
  return m;
}

TaskStatus read_status(const fs::path& job, int id) {
  TaskStatus s;
  std::ifstream in(task_status_path(job, id));
  if (!in) return s;
  const json doc = json::parse(in, nullptr, false);
  if (!doc.is_object()) return s;
  s.state = doc.value("state", "pending");
  s.exit = doc.value("exit", -1);
  s.attempts = doc.value("attempts", 0);
  s.seconds = doc.value("seconds", 0.0);
  s.host = doc.value("host", "");
  s.message = doc.value("message", "");
  s.pid = doc.value("pid", 0L);
  s.loom = doc.value("loom", "");
  if (doc.contains("tries") && doc["tries"].is_array())
    for (const json& t : doc["tries"])
      if (t.is_object()) s.tries.push_back({t.value("host", ""), t.value("end", ""), t.value("seconds", 0.0)});
  return s;
}

void write_status(const fs::path& job, int id, const TaskStatus& s) {
  const json doc = {{"state", s.state},     {"exit", s.exit}, {"attempts", s.attempts},
                    {"seconds", s.seconds}, {"host", s.host}, {"message", s.message},
                    {"pid", s.pid}};
  json written = doc;
  written["loom"] = s.loom;
  written["tries"] = json::array();
  for (const TaskTry& t : s.tries)
    written["tries"].push_back({{"host", t.host}, {"end", t.end}, {"seconds", t.seconds}});
  write_file_atomic(task_status_path(job, id), written.dump(2) + "\n");
}

}  // namespace loom::runner
