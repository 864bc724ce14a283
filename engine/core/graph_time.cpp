#include "graph_time.hpp"

#include "json_text.hpp"

namespace loom::detail {

TimeRange parse_time(const json& t) {
  std::vector<GraphIssue> issues;
  TimeRange r;
  if (!t.is_object())
    throw GraphError("", {{"/time", "expected {\"start\": 1, \"end\": 48, \"fps\": 24}, got " + describe_json(t)}});
  for (const auto& [key, value] : t.items())
    if (key != "start" && key != "end" && key != "fps")
      issues.push_back({"/time/" + pointer_escape(key), "unknown key (expected \"start\", \"end\" or \"fps\")"});
  auto frame = [&](const char* key, int fallback) {
    if (!t.contains(key)) return fallback;
    const json& v = t[key];
    if (!v.is_number_integer()) {
      issues.push_back({std::string("/time/") + key, "expected a frame number (an integer), got " + describe_json(v)});
      return fallback;
    }
    if (v.get<long long>() < -kMaxFrame || v.get<long long>() > kMaxFrame) {
      issues.push_back({std::string("/time/") + key, "frame " + v.dump() + " is beyond the frame numbers Loom runs: " +
                                                         "expected between " + std::to_string(-kMaxFrame) +
                                                         " and " + std::to_string(kMaxFrame)});
      return fallback;
    }
    return static_cast<int>(v.get<long long>());
  };
  r.start = frame("start", 1);
  r.end = frame("end", r.start);
  if (t.contains("fps")) {
    const json& v = t["fps"];
    if (!v.is_number() || !(v.get<double>() > 0) || v.get<double>() > 1e6)
      issues.push_back({"/time/fps", "expected frames per second (a number above 0), got " + describe_json(v)});
    else
      r.fps = v.get<double>();
  }
  if (r.end < r.start)
    issues.push_back({"/time/end", "the end frame " + std::to_string(r.end) + " is before the start frame " +
                                       std::to_string(r.start)});
  if (!issues.empty()) throw GraphError("", issues);
  return r;
}

json time_to_json(const TimeRange& r) { return {{"start", r.start}, {"end", r.end}, {"fps", r.fps}}; }

FrameTime graph_time(const Graph& graph) {
  FrameTime time;
  if (graph.time) {
    time.start = graph.time->start;
    time.fps = graph.time->fps;
  }
  return time;
}

}  // namespace loom::detail
