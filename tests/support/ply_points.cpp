#include "ply_points.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace loom::test {

namespace {

template <class T>
double take(const std::string& bytes, std::size_t& at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  at += sizeof v;
  return static_cast<double>(v);
}

}  // namespace

PlyPoints read_ply_points(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string bytes = ss.str();
  PlyPoints p;
  const std::size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos) << path;
  if (end == std::string::npos) return p;
  std::istringstream header(bytes.substr(0, end));
  std::string line, word;
  std::getline(header, line);
  EXPECT_EQ(line, "ply");
  std::vector<std::pair<std::string, std::string>> props;  // type, name
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    ls >> word;
    if (word == "format") {
      ls >> word;
      EXPECT_EQ(word, "binary_little_endian");
    } else if (word == "element") {
      ls >> word >> p.count;
      EXPECT_EQ(word, "vertex");
    } else if (word == "property") {
      std::string type, name;
      ls >> type >> name;
      p.properties.push_back(type + " " + name);
      props.emplace_back(type, name);
    }
  }
  std::size_t at = end + 11;
  for (long i = 0; i < p.count; ++i)
    for (const auto& [type, name] : props) {
      std::vector<double>& column = p.columns[name];
      if (type == "float")
        column.push_back(take<float>(bytes, at));
      else if (type == "double")
        column.push_back(take<double>(bytes, at));
      else if (type == "uchar")
        column.push_back(take<std::uint8_t>(bytes, at));
      else
        ADD_FAILURE() << "unexpected property type " << type;
      if (at > bytes.size()) {
        ADD_FAILURE() << "the file ends inside vertex " << i;
        return p;
      }
    }
  EXPECT_EQ(at, bytes.size()) << "bytes after the last vertex";
  return p;
}

}  // namespace loom::test
