#include "embree_tutorial.hpp"

#include <chrono>
#include <cstdlib>

#include <sys/resource.h>
#include <unistd.h>

namespace loom::pathtrace::bench {

namespace {

// CPU seconds (user + system, all threads) of this process's finished children.
double children_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

bool embree_tutorial_installed() {
  return std::system("command -v pathtracer > /dev/null 2>&1") == 0 &&
         std::filesystem::exists(std::filesystem::path(EMBREE_MODELS) / "cornell_box.ecs");
}

std::filesystem::path tutorial_scratch(const std::string& suffix) {
  return std::filesystem::temp_directory_path() / ("loom-bench-embree-" + std::to_string(getpid()) + suffix);
}

double run_embree_tutorial(int size, int spp, int depth, int threads, const std::filesystem::path& out, double* cpu,
                           const std::string& environment) {
  const std::string cmd = environment + " pathtracer -c '" + std::string(EMBREE_MODELS) + "/cornell_box.ecs' --size " +
                          std::to_string(size) + " " + std::to_string(size) + " --spp " + std::to_string(spp) +
                          " --max-path-length " + std::to_string(depth) + " --threads " + std::to_string(threads) +
                          " -o '" + out.string() + "' > /dev/null 2>&1";
  const auto t = std::chrono::steady_clock::now();
  const double c0 = children_cpu_seconds();
  const int rc = std::system(cmd.c_str());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  if (cpu) *cpu = children_cpu_seconds() - c0;
  return rc == 0 ? s : -1;
}

TutorialSeconds time_embree_tutorial(int size, int spp, int depth, int threads, const std::filesystem::path& out) {
  double cpu_full = 0, cpu_one = 0;
  const double wall_full = run_embree_tutorial(size, spp, depth, threads, out, &cpu_full);
  const double wall_one = run_embree_tutorial(size, 1, depth, threads, out, &cpu_one);
  const double scale = double(spp) / (spp - 1);
  return {(wall_full - wall_one) * scale, (cpu_full - cpu_one) * scale};
}

}  // namespace loom::pathtrace::bench
