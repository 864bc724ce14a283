#include "test_files.hpp"

#include <fstream>
#include <random>
#include <sstream>

namespace loom::test {

namespace fs = std::filesystem;

fs::path data_file(const std::string& relative) {
  fs::path p = fs::path(LOOM_DATA_DIR) / relative;
  return fs::exists(p) ? p : fs::path();
}

fs::path temp_dir() {
  static std::mt19937_64 rng(std::random_device{}());
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "loom";
  fs::path dir = fs::temp_directory_path() / ("loom-test-" + name + "-" + std::to_string(rng() % 1000000));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace loom::test
