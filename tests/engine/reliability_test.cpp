// The second hostile probe's defects (issue 30), each as a regression test of
// the real runner: symlinks out of --out, the cache deleting files it does not
// own, FIFOs named inside scene files, signals during a write, full disks,
// memory bombs in scene files, unclear errors.
#include <sys/stat.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <tuple>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "image_codec.hpp"
#include "loom/graph.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"
#include "video_codec.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

// The runner with the test plugins on its path, as a shell command (so tests
// can wrap it in ulimit, a pipe, or a background job).
std::string loom_cmd(const std::string& args) {
  return "env LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " " + test::fresh_cache_env(args) + LOOM_RUNNER + " " + args;
}

fs::path write_file(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

fs::path write_graph(const fs::path& dir, const json& nodes, const json& time = nullptr) {
  json g = {{"loom", 1}, {"nodes", nodes}};
  if (!time.is_null()) g["time"] = time;
  return write_file(dir / "g.json", g.dump());
}

json from(const std::string& link) { return {{"from", link}}; }

void age(const fs::path& file) {
  fs::last_write_time(file, fs::file_time_type::clock::now() - std::chrono::hours(2));
}

// Staging files of any Loom writer, old naming included, anywhere under dir.
std::vector<std::string> staging_files(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(".loomtmp", 0) == 0 || name.find(".tmp") != std::string::npos) found.push_back(name);
  }
  return found;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---- item 2: the cache deletes only its own files --------------------------

TEST(Reliability, TheCacheRefusesAFolderThatIsNotACacheAndTouchesNothingInIt) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, {{"s", {{"type", "Sleep"}, {"inputs", {{"ms", 1}}}}},
                             {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("s.value")}, {"path", "x.txt"}}}}}});
  const fs::path proj = dir / "proj";
  age(write_file(proj / ".env", "SECRET=1"));
  age(write_file(proj / "sub" / ".gitignore", "*"));
  std::string out;
  EXPECT_EQ(test::run_shell(loom_cmd("run " + g.string() + " --out " + (dir / "o").string() + " --cache " +
                                     proj.string()), &out), 2) << out;
  EXPECT_NE(out.find("is not a Loom cache"), std::string::npos) << out;
  EXPECT_EQ(test::run_shell(loom_cmd("cache clear --cache " + proj.string()), &out), 2) << out;
  EXPECT_TRUE(fs::exists(proj / ".env"));
  EXPECT_TRUE(fs::exists(proj / "sub" / ".gitignore"));
  EXPECT_FALSE(fs::exists(proj / "CACHEDIR.TAG"));
}

TEST(Reliability, TrimAndClearDeleteOnlyTheCachesEntriesAndStagingFiles) {
  auto dir = test::temp_dir();
  const fs::path cache = dir / "cache";
  auto g = write_graph(dir, {{"s", {{"type", "Sleep"}, {"inputs", {{"ms", 300}}}}},
                             {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("s.value")}, {"path", "x.txt"}}}}}});
  const std::string run = "run " + g.string() + " -q --out " + (dir / "o").string() + " --cache " + cache.string() +
                          " --cache-min-seconds 0";
  std::string out;
  ASSERT_EQ(test::run_shell(loom_cmd(run), &out), 0) << out;
  ASSERT_TRUE(fs::exists(cache / "CACHEDIR.TAG"));
  // A user's files beside and inside the cache's folders, all old.
  age(write_file(cache / ".env", "SECRET=1"));
  age(write_file(cache / "ab" / ".gitignore", "*"));
  age(write_file(cache / "notes" / ".keep", ""));
  age(write_file(cache / "ab" / "abcdef0123456789.loomcache.bak", "mine"));
  // The cache's own: an entry and abandoned staging files of both namings.
  write_file(cache / "ab" / "abcdef0123456789.loomcache", std::string(10000, 'x'));  // not even a valid entry
  age(write_file(cache / "ab" / ".loomtmp-99-0.loomcache", ""));
  age(write_file(cache / "ab" / ".abcdef0123456789.loomcache.tmp99.0", ""));
  // A limit the new entry fits in (a quarter of it: the storage rule) and the
  // old one does not: storing triggers the trim.
  ASSERT_EQ(test::run_shell(loom_cmd(run + " --set s.ms=301 --cache-limit 0.005"), &out), 0) << out;
  EXPECT_FALSE(fs::exists(cache / "ab" / ".loomtmp-99-0.loomcache"));
  EXPECT_FALSE(fs::exists(cache / "ab" / ".abcdef0123456789.loomcache.tmp99.0"));
  EXPECT_FALSE(fs::exists(cache / "ab" / "abcdef0123456789.loomcache"));  // least recently used, over the limit
  ASSERT_EQ(test::run_shell(loom_cmd("cache clear --cache " + cache.string()), &out), 0) << out;
  ASSERT_EQ(test::run_shell(loom_cmd("cache info --cache " + cache.string()), &out), 0) << out;
  EXPECT_NE(out.find("entries: 0"), std::string::npos) << out;
  for (const char* mine : {".env", "ab/.gitignore", "notes/.keep", "ab/abcdef0123456789.loomcache.bak"})
    EXPECT_TRUE(fs::exists(cache / mine)) << mine;
}

// ---- item 4: no write outside --out through a symbolic link -----------------

TEST(Reliability, ASymlinkedFolderCannotLeadAWriteOutOfTheOutputFolder) {
  auto dir = test::temp_dir();
  fs::create_directories(dir / "outside");
  fs::create_directories(dir / "out" / "inside");
  fs::create_directory_symlink("../outside", dir / "out" / "link");
  fs::create_directory_symlink("inside", dir / "out" / "alias");
  const json sources = {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {16, 16}}}}}},
                        {"sphere", {{"type", "UVSphere"}, {"inputs", {{"rings", 4}, {"segments", 8}}}}}};
  const json time = {{"start", 1}, {"end", 2}, {"fps", 24}};
  auto run = [&](const json& writer, std::string* out) {
    json nodes = sources;
    nodes["w"] = writer;
    auto g = write_graph(dir, nodes, time);
    return test::run_shell(loom_cmd("run " + g.string() + " --out " + (dir / "out").string()), out);
  };
  std::string out;
  for (const char* path : {"link/x", "link/sub/deep/y"}) {
    for (const auto& [type, port, link, ext] :
         {std::tuple<const char*, const char*, const char*, const char*>{"SaveImage", "image", "board.image", ".png"},
          {"SaveMesh", "mesh", "sphere.mesh", ".obj"},
          {"SaveVideo", "image", "board.image", ".mp4"}}) {
      // A literal path is refused when the graph is bound (exit 2), a linked one when the node runs (exit 1).
      EXPECT_EQ(run({{"type", type}, {"inputs", {{port, from(link)}, {"path", std::string(path) + ext}}}}, &out), 2)
          << type << " " << path << "\n" << out;
      EXPECT_NE(out.find("leads out of the output folder through a symbolic link"), std::string::npos) << out;
    }
  }
  json linked = sources;
  linked["p"] = {{"type", "StringConstant"}, {"inputs", {{"value", "link/sub/z.png"}}}};
  linked["w"] = {{"type", "SaveImage"}, {"inputs", {{"image", from("board.image")}, {"path", from("p.value")}}}};
  const fs::path g = write_file(dir / "linked.json", json{{"loom", 1}, {"nodes", linked}}.dump());
  EXPECT_EQ(test::run_shell(loom_cmd("run " + g.string() + " --out " + (dir / "out").string()), &out), 1) << out;
  EXPECT_NE(out.find("through a symbolic link"), std::string::npos) << out;
  EXPECT_TRUE(fs::is_empty(dir / "outside"));
  // A link that stays inside --out is followed; --allow-outside-out lifts the rule.
  EXPECT_EQ(run({{"type", "SaveImage"}, {"inputs", {{"image", from("board.image")}, {"path", "alias/ok.png"}}}}, &out), 0)
      << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "inside" / "ok.png"));
  EXPECT_EQ(test::run_shell(loom_cmd("run " + g.string() + " --out " + (dir / "out").string() +
                                     " --allow-outside-out -q"), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "outside" / "sub" / "z.png"));
}

// ---- item 5a: FIFOs inside scene files, and a node that ignores cancel ------

void make_fifo(const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0) << p; }

TEST(Reliability, AFifoNamedAnywhereIsRefusedNotOpened) {
  auto dir = test::temp_dir();
  make_fifo(dir / "fifo.mtl");
  make_fifo(dir / "fifo.png");
  make_fifo(dir / "fifo.bin");
  make_fifo(dir / "fifo.obj");
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
  write_file(dir / "mtl.obj", "mtllib fifo.mtl\n" + triangle);
  write_file(dir / "tex.obj", "mtllib tex.mtl\n" + triangle);
  write_file(dir / "tex.mtl", "newmtl m\nKd 1 1 1\nmap_Kd fifo.png\n");
  write_file(dir / "buf.gltf",
             R"({"asset":{"version":"2.0"},"buffers":[{"uri":"fifo.bin","byteLength":36}],
                 "bufferViews":[{"buffer":0,"byteLength":36}],
                 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
                 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
  auto run = [&](const json& node, const std::string& target, std::string* out) {
    auto g = write_graph(dir, {{"n", node}});
    const auto start = std::chrono::steady_clock::now();
    const int code = test::run_shell("timeout -k 5 20 " + loom_cmd("run " + g.string() + " --target " + target +
                                                                  " --out " + (dir / "o").string()), out);
    EXPECT_LT(seconds_since(start), 15) << *out;
    return code;
  };
  std::string out;
  for (const char* scene : {"mtl.obj", "buf.gltf"}) {
    EXPECT_EQ(run({{"type", "LoadScene"}, {"inputs", {{"path", scene}}}}, "n.scene", &out), 1) << scene << out;
    EXPECT_NE(out.find("FIFO"), std::string::npos) << out;
  }
  EXPECT_EQ(run({{"type", "LoadScene"}, {"inputs", {{"path", "tex.obj"}}}}, "n.scene", &out), 0) << out;
  EXPECT_NE(out.find("fifo.png: it is a FIFO"), std::string::npos) << out;  // a warning: the material goes without it
  EXPECT_EQ(run({{"type", "LoadMesh"}, {"inputs", {{"path", "fifo.obj"}}}}, "n.mesh", &out), 1) << out;
  EXPECT_NE(out.find("FIFO"), std::string::npos) << out;
  EXPECT_EQ(run({{"type", "LoadImage"}, {"inputs", {{"path", "fifo.png"}}}}, "n.image", &out), 1) << out;
  EXPECT_NE(out.find("FIFO"), std::string::npos) << out;
}

TEST(Reliability, ASignalEndsARunWhoseNodeIgnoresCancellationWithinTheGrace) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, {{"stuck", {{"type", "Unresponsive"}, {"inputs", {{"ms", 60000}}}}},
                             {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("stuck.value")}, {"path", "x.txt"}}}}}});
  std::string out;
  const auto start = std::chrono::steady_clock::now();
  // The signal goes once the node is running (its log line is out), not while plugins load.
  const std::string log = (dir / "log.txt").string();
  const int code = test::run_shell(loom_cmd("run " + g.string() + " --out " + (dir / "o").string()) + " > " + log +
                                       " 2>&1 & pid=$!; for i in $(seq 400); do grep -q sleeping " + log +
                                       " && break; sleep 0.05; done; kill -TERM $pid; wait $pid; rc=$?; cat " + log +
                                       "; exit $rc", &out);
  const double took = seconds_since(start);
  EXPECT_EQ(code, 130) << out;
  EXPECT_LT(took, 5) << out;     // 0.3 s of grace, not the node's 60 s
  EXPECT_GT(took, 0.25) << out;  // and the grace is given
  EXPECT_NE(out.find("nodes still running 0.3 s after the signal"), std::string::npos) << out;
  EXPECT_NE(out.find("error: interrupted by SIGTERM"), std::string::npos) << out;
}

// ---- item 6: staging files under every signal; full disks -------------------

// A video long enough to be interrupted while its staging file exists.
fs::path video_graph(const fs::path& dir, int frames) {
  return write_graph(dir,
                     {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {640, 480}}, {"cells", 24}}}}},
                      {"v", {{"type", "SaveVideo"}, {"inputs", {{"image", from("board.image")}, {"path", "twist.mp4"}}}}}},
                     json{{"start", 1}, {"end", frames}, {"fps", 24}});
}

// Starts the run in the background, waits for its staging file, then runs
// `signal_script` (which may use $pid) and waits for the run to end.
int interrupt_video(const fs::path& dir, const std::string& launch, const std::string& signal_script, std::string* out) {
  const std::string wait_staging = "for i in $(seq 200); do ls -a " + (dir / "out").string() +
                                   " 2>/dev/null | grep -q loomtmp && break; sleep 0.05; done; ";
  return test::run_shell(launch + " & pid=$!; " + wait_staging + signal_script + "; wait $pid", out);
}

TEST(Reliability, HangupPipeAndASecondTermLeaveNoStagingFile) {
  for (const std::string how : {"hup", "term-term", "pipe"}) {
    auto dir = test::temp_dir();
    auto g = video_graph(dir, 3000);
    const std::string run = loom_cmd("run " + g.string() + " --out " + (dir / "out").string());
    std::string out;
    int code;
    if (how == "pipe") {  // the reader of the output goes away: SIGPIPE at the next progress line
      test::run_shell("( " + run + " 2>&1; echo $? > " + (dir / "rc").string() + " ) | head -c 1 >/dev/null", &out);
      std::ifstream(dir / "rc") >> code;
    } else {
      code = interrupt_video(dir, run + " >/dev/null 2>&1",
                             how == "hup" ? "kill -HUP $pid" : "kill -TERM $pid; kill -TERM $pid", &out);
    }
    EXPECT_EQ(code, 130) << how << "\n" << out;
    EXPECT_TRUE(staging_files(dir / "out").empty()) << how << ": " << staging_files(dir / "out").front();
    EXPECT_FALSE(fs::exists(dir / "out" / "twist.mp4")) << how;
  }
}

// A file-size limit (ulimit -f) stands in for a full disk: every write past
// it fails, as on a full disk, without needing one.
TEST(Reliability, AFullDiskFailsSaveVideoAndSaveMeshAndLeavesNoFile) {
  auto dir = test::temp_dir();
  cv::Mat noise(256, 256, CV_32FC3);
  cv::randu(noise, 0, 1);
  io::write_image(Image(noise, Encoding::srgb), dir / "noise.png", io::Depth::u8);
  const json video = {
      {"noise", {{"type", "LoadImage"}, {"inputs", {{"path", "noise.png"}}}}},
      {"v", {{"type", "SaveVideo"}, {"inputs", {{"image", from("noise.image")}, {"path", "twist.mp4"}, {"codec", "mp4v"}}}}}};
  const json mesh = {{"sphere", {{"type", "UVSphere"}, {"inputs", {{"rings", 200}, {"segments", 400}}}}},
                     {"m", {{"type", "SaveMesh"}, {"inputs", {{"mesh", from("sphere.mesh")}, {"path", "m.obj"}}}}}};
  const json frames = {{"start", 1}, {"end", 48}, {"fps", 24}};
  std::string out;
  for (const auto& [nodes, files] : {std::pair<json, std::vector<std::string>>{video, {"twist.mp4"}},
                                     {mesh, {"m.obj", "m.mtl"}}}) {
    auto g = write_graph(dir, nodes, nodes.contains("v") ? frames : json());
    const std::string run = loom_cmd("run " + g.string() + " --no-cache --out " + (dir / "out").string());
    const int code = test::run_shell("ulimit -f 256; " + run, &out);  // 256 KB
    EXPECT_EQ(code, 1) << out;
    EXPECT_NE(out.find("cannot write"), std::string::npos) << out;
    EXPECT_EQ(out.find("wrote "), std::string::npos) << out;
    for (const auto& f : files) EXPECT_FALSE(fs::exists(dir / "out" / f)) << f;
    EXPECT_TRUE(staging_files(dir / "out").empty());
    // Without the limit the same graph writes every file.
    ASSERT_EQ(test::run_shell(run + " -q", &out), 0) << out;
    for (const auto& f : files) EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    fs::remove_all(dir / "out");
  }
}

// ---- item 7: memory bombs in scene files --------------------------------

// A PNG whose header declares width × height; the pixels are never read.
std::string png_header(std::uint32_t width, std::uint32_t height) {
  std::string b("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (std::uint32_t v : {width, height})
    for (int s = 24; s >= 0; s -= 8) b += static_cast<char>((v >> s) & 0xff);
  b += std::string("\x08\x02\0\0\0", 5) + std::string(4, '\0') + std::string(1000, '\0');
  return b;
}

// A GLB of one triangle; `image` (when not empty) embedded as its base colour map.
std::string glb(const std::string& image, std::uint32_t json_length_override = 0) {
  std::string bin(36, '\0');
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::memcpy(bin.data(), p, sizeof p);
  json j = {{"asset", {{"version", "2.0"}}},
            {"buffers", {{{"byteLength", 36 + image.size()}}}},
            {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}}},
            {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                            {"min", {0, 0, 0}}, {"max", {1, 1, 0}}}}},
            {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"material", 0}}}}}}},
            {"materials", {{{"pbrMetallicRoughness", json::object()}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"scenes", {{{"nodes", {0}}}}}};
  if (!image.empty()) {
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", image.size()}});
    j["images"] = {{{"bufferView", 1}, {"mimeType", "image/png"}}};
    j["textures"] = {{{"source", 0}}};
    j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    bin += image;
  }
  std::string text = j.dump();
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin += '\0';
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::uint32_t json_length = json_length_override ? json_length_override : static_cast<std::uint32_t>(text.size());
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size())) + u32(json_length) +
         "JSON" + text + u32(static_cast<std::uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
}

// Under a 3 GB address-space limit: a bomb that allocates first fails here.
int run_limited(const fs::path& dir, const json& node, const std::string& target, std::string* out) {
  auto g = write_graph(dir, {{"n", node}});
  return test::run_shell("ulimit -v 3000000; " + loom_cmd("run " + g.string() + " --target " + target + " --out " +
                                                           (dir / "o").string()), out);
}

TEST(Reliability, ATextureDeclaringTooManyPixelsIsRefusedBeforeDecoding) {
  auto dir = test::temp_dir();
  write_file(dir / "huge.png", png_header(20000, 20000));
  write_file(dir / "scene.obj", "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
  write_file(dir / "scene.mtl", "newmtl m\nKd 1 1 1\nmap_Kd huge.png\n");
  write_file(dir / "scene.glb", glb(png_header(20000, 20000)));
  std::string out;
  for (const char* scene : {"scene.obj", "scene.glb"}) {
    EXPECT_EQ(run_limited(dir, {{"type", "LoadScene"}, {"inputs", {{"path", scene}}}}, "n.scene", &out), 0)
        << scene << out;
    EXPECT_NE(out.find("20000×20000 pixels, more than the limit of 268435456"), std::string::npos) << scene << out;
  }
}

TEST(Reliability, AGlbChunkLongerThanTheFileIsRefused) {
  auto dir = test::temp_dir();
  write_file(dir / "bomb.glb", glb("", 0xfffffff0u));
  std::string out;
  EXPECT_EQ(run_limited(dir, {{"type", "LoadScene"}, {"inputs", {{"path", "bomb.glb"}}}}, "n.scene", &out), 1) << out;
  EXPECT_NE(out.find("a GLB chunk claims 4294967280 bytes"), std::string::npos) << out;
  EXPECT_EQ(run_limited(dir, {{"type", "LoadMesh"}, {"inputs", {{"path", "bomb.glb"}}}}, "n.mesh", &out), 1) << out;
  write_file(dir / "fine.glb", glb(""));  // the same file with its true length loads
  EXPECT_EQ(run_limited(dir, {{"type", "LoadScene"}, {"inputs", {{"path", "fine.glb"}}}}, "n.scene", &out), 0) << out;
}

TEST(Reliability, AGltfNodeTreeThatExpandsExponentiallyIsRefused) {
  auto dir = test::temp_dir();
  json nodes = json::array();
  for (int i = 0; i < 40; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
  nodes.push_back({{"mesh", 0}});
  write_file(dir / "tree.gltf",
             json{{"asset", {{"version", "2.0"}}},
                  {"buffers", {{{"uri", "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"},
                                {"byteLength", 36}}}},
                  {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}}},
                  {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                                  {"min", {0, 0, 0}}, {"max", {1, 1, 0}}}}},
                  {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
                  {"nodes", nodes},
                  {"scenes", {{{"nodes", {0}}}}}}
                 .dump());
  std::string out;
  EXPECT_EQ(run_limited(dir, {{"type", "LoadScene"}, {"inputs", {{"path", "tree.gltf"}}}}, "n.scene", &out), 1) << out;
  EXPECT_NE(out.find("expands to more than 100000 node instances"), std::string::npos) << out;
  // A chain of the same 41 nodes (each child listed once) loads.
  for (int i = 0; i < 40; ++i) nodes[i]["children"] = {i + 1};
  auto doc = json::parse(std::ifstream(dir / "tree.gltf"));
  doc["nodes"] = nodes;
  write_file(dir / "tree.gltf", doc.dump());
  EXPECT_EQ(run_limited(dir, {{"type", "LoadScene"}, {"inputs", {{"path", "tree.gltf"}}}}, "n.scene", &out), 0) << out;
}

TEST(Reliability, RandomSamplingCountIsBoundedBeforeAllocating) {
  auto dir = test::temp_dir();
  std::string out;
  EXPECT_EQ(run_limited(dir, {{"type", "MPMEmitBox"}, {"inputs", {{"sampling", "random"}, {"count", 2147483647}}}},
                        "n.particles", &out), 2) << out;
  EXPECT_NE(out.find("out of range"), std::string::npos) << out;
}

// ---- item 8: clear errors ------------------------------------------------

TEST(Reliability, SaveVideoIntoAFolderItCannotWriteSaysSo) {
  auto dir = test::temp_dir();
  // Root writes into a read-only folder anyway; /sys refuses new files even to root.
  fs::path out_dir = ::geteuid() == 0 ? fs::path("/sys") : dir / "ro";
  if (::geteuid() != 0) {
    fs::create_directories(out_dir);
    fs::permissions(out_dir, fs::perms::owner_read | fs::perms::owner_exec);
  }
  auto g = video_graph(dir, 2);
  std::string out;
  EXPECT_EQ(test::run_shell(loom_cmd("run " + g.string() + " --out " + out_dir.string()), &out), 1) << out;
  EXPECT_NE(out.find("twist.mp4: Permission denied"), std::string::npos) << out;
  EXPECT_EQ(out.find("FFmpeg"), std::string::npos) << out;
}

TEST(Reliability, AFileNameOfTheFileSystemsFullLengthIsWritten) {
  auto dir = test::temp_dir();
  const std::string name = std::string(251, 'a') + ".png";  // 255 bytes, NAME_MAX
  auto g = write_graph(dir, {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {8, 8}}}}}},
                             {"s", {{"type", "SaveImage"}, {"inputs", {{"image", from("board.image")}, {"path", name}}}}}});
  std::string out;
  EXPECT_EQ(test::run_shell(loom_cmd("run " + g.string() + " -q --out " + (dir / "out").string()), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / name));
}

// ---- item 9: a video's frames all have one size ----------------------------

TEST(Reliability, SaveVideoRefusesAFrameOfAnotherSizeEvenWhenPaddingWouldHideIt) {
  auto dir = test::temp_dir();
  io::VideoSequence video(dir / "v.mp4", 24, io::VideoCodec::mpeg4);
  video.add(Image(cv::Mat(17, 33, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), Encoding::srgb));
  try {
    video.add(Image(cv::Mat(18, 34, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), Encoding::srgb));
    FAIL() << "a 34x18 frame after a 33x17 one was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 2 is 34x18 but the video's frames are 33x17"), std::string::npos)
        << e.what();
  }
}

// ---- item 10: long set-up work reports progress ---------------------------

TEST(Reliability, PoissonDiskSamplingReportsProgress) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, {{"e", {{"type", "MPMEmitBox"},
                                    {"inputs", {{"dimension", 3}, {"sampling", "poisson"}, {"spacing", 0.012},
                                                {"min", {0.2, 0.2, 0.2}}, {"max", {0.8, 0.8, 0.8}}}}}}});
  std::string out;
  ASSERT_EQ(test::run_shell(loom_cmd("run " + g.string() + " --target e.particles --out " + (dir / "o").string()), &out),
            0) << out;
  EXPECT_NE(out.find("[e] 25% placing particles"), std::string::npos) << out;
  EXPECT_NE(out.find("[e] 75% placing particles"), std::string::npos) << out;
}

}  // namespace
}  // namespace loom
