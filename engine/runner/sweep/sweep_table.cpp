#include "sweep/sweep_table.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

#include "loom/atomic_file.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

namespace {

using Row = std::map<std::string, json>;

// p[key] when it is an object, else an empty object.
const json& object_at(const json& p, const char* key) {
  static const json empty = json::object();
  auto it = p.find(key);
  return it != p.end() && it->is_object() ? *it : empty;
}

// Numbers stay numbers, a bool is 0 or 1, an object gives a column per
// numeric leaf (name.key...), a list of numbers its last value.
void flatten(const std::string& name, const json& v, std::vector<std::pair<std::string, json>>& cells) {
  if (v.is_number()) cells.emplace_back(name, v);
  else if (v.is_boolean()) cells.emplace_back(name, v.get<bool>() ? 1 : 0);
  else if (v.is_object())
    for (const auto& [key, leaf] : v.items()) flatten(name + "." + key, leaf, cells);
  else if (v.is_array() && !v.empty() && v.back().is_number()) cells.emplace_back(name, v.back());
}

// RFC 4180: a cell with a comma, quote or line break is quoted, quotes doubled.
std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  const std::string plain = v.is_string() ? v.get<std::string>() : v.dump();
  if (plain.find_first_of(",\"\n\r") == std::string::npos) return plain;
  std::string text = "\"";
  for (char c : plain) text += c == '"' ? std::string("\"\"") : std::string(1, c);
  return text + "\"";
}

// The columns in order and one row per point.
std::vector<std::string> tabulate(const std::vector<SweepAxis>& axes, const std::vector<json>& points,
                                  std::vector<Row>& rows) {
  std::vector<std::string> columns = {"point"};
  for (const auto& a : axes) columns.push_back(a.input);
  columns.insert(columns.end(), {"status", "source", "seconds", "run_seconds"});
  std::set<std::string> node_columns;
  std::vector<std::string> record_columns;
  for (const json& p : points) {
    Row row = {{"point", p["index"]},
               {"status", p["status"]},
               {"source", p.value("source", json())},
               {"seconds", p.value("seconds", json())},
               {"run_seconds", p.value("run_seconds", json())}};
    for (const auto& a : axes) row[a.input] = p["values"].value(a.input, json());
    for (const auto& [id, n] : object_at(p, "nodes").items()) {
      row[id + ".seconds"] = n["seconds"];
      node_columns.insert(id + ".seconds");
    }
    std::vector<std::pair<std::string, json>> cells;
    for (const auto& [name, v] : object_at(p, "records").items()) flatten(name, v, cells);
    for (auto& [name, v] : cells) {
      if (std::find(record_columns.begin(), record_columns.end(), name) == record_columns.end())
        record_columns.push_back(name);
      row[name] = v;
    }
    rows.push_back(std::move(row));
  }
  columns.insert(columns.end(), node_columns.begin(), node_columns.end());
  columns.insert(columns.end(), record_columns.begin(), record_columns.end());
  return columns;
}

std::string plot_name(const std::string& x, const std::string& y) {
  std::string name = "sweep_" + x + "_" + y + ".png";
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  return name;
}

// Y against X over the points where both are numbers, sorted by X.
bool plot(const fs::path& out, const std::string& spec, const std::vector<std::string>& columns,
          const std::vector<Row>& rows, bool quiet) {
  const std::size_t colon = spec.find(':');
  const std::string x = spec.substr(0, colon), y = colon == std::string::npos ? "" : spec.substr(colon + 1);
  for (const auto& c : {x, y})
    if (std::find(columns.begin(), columns.end(), c) == columns.end()) {
      std::string known;
      for (const auto& k : columns) known += (known.empty() ? "" : ", ") + k;
      std::cerr << "error: --plot " << spec << ": no column \"" << c << "\" in sweep.csv (columns: " << known << ")\n";
      return false;
    }
  std::vector<std::pair<double, double>> xy;
  for (const Row& r : rows) {
    auto a = r.find(x), b = r.find(y);
    if (a != r.end() && b != r.end() && a->second.is_number() && b->second.is_number())
      xy.emplace_back(a->second.get<double>(), b->second.get<double>());
  }
  std::sort(xy.begin(), xy.end());
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::cerr << "note: gnuplot not found, no plot for " << spec << " (apt-get install gnuplot-nox)\n";
    return true;
  }
  const fs::path png = out / plot_name(x, y), partial = out / ("." + plot_name(x, y) + ".partial");
  FILE* gp = ::popen("gnuplot", "w");
  if (!gp) return false;
  std::fprintf(gp, "set terminal pngcairo size 800,560 noenhanced\nset output '%s'\nset grid\n"
               "set xlabel '%s'\nset ylabel '%s'\nset title 'loom sweep: %s against %s'\n"
               "plot '-' using 1:2 with linespoints pointtype 7 title '%s'\n",
               partial.c_str(), x.c_str(), y.c_str(), y.c_str(), x.c_str(), y.c_str());
  for (const auto& [a, b] : xy) std::fprintf(gp, "%.17g %.17g\n", a, b);
  std::fprintf(gp, "e\n");
  const bool ok = ::pclose(gp) == 0;
  std::error_code ec;
  if (ok) fs::rename(partial, png, ec);
  if (!ok || ec) {
    fs::remove(partial, ec);
    std::cerr << "error: gnuplot could not draw " << png.string() << "\n";
    return false;
  }
  if (!quiet) std::cerr << "plot: " << png.string() << "\n";
  return true;
}

}  // namespace

bool write_sweep_tables(const fs::path& out, const std::vector<SweepAxis>& axes, const std::vector<json>& points,
                        const std::vector<std::string>& plots, bool quiet) {
  std::vector<Row> rows;
  const auto columns = tabulate(axes, points, rows);
  std::string csv;
  for (std::size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + columns[c];
  csv += "\n";
  for (const Row& r : rows) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      auto it = r.find(columns[c]);
      csv += (c ? "," : "") + (it == r.end() ? std::string() : csv_cell(it->second));
    }
    csv += "\n";
  }
  // How often each node ran, against being served from the cache: what the
  // points shared (a node upstream of every swept input runs once).
  json sharing = json::object();
  for (const json& p : points)
    for (const auto& [id, n] : object_at(p, "nodes").items()) {
      json& counts = sharing[id];
      if (!counts.is_object()) counts = json::object();
      const std::string status = n["status"];
      counts[status] = counts.value(status, 0) + 1;
    }
  json axes_json = json::array();
  for (const auto& a : axes) axes_json.push_back({{"input", a.input}, {"values", a.values}});
  const json doc = {{"axes", axes_json}, {"columns", columns}, {"points", points}, {"nodes", sharing}};
  try {
    fs::create_directories(out);
    write_file_atomic(out / "sweep.csv", csv);
    write_file_atomic(out / "sweep.json", doc.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return false;
  }
  if (!quiet) {
    std::cerr << "sweep: " << (out / "sweep.csv").string() << " (" << rows.size() << " points)\n";
    for (const auto& [id, counts] : sharing.items())
      if (counts.value("cached", 0) > 0)
        std::cerr << "  " << id << ": ran at " << counts.value("ran", 0) << " points, cached at "
                  << counts.value("cached", 0) << "\n";
  }
  bool ok = true;
  for (const auto& p : plots) ok = plot(out, p, columns, rows, quiet) && ok;
  return ok;
}

}  // namespace loom::runner
