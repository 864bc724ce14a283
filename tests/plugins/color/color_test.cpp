// Loom's OpenColorIO config and ColorConvert / DisplayView, checked against
// OpenColorIO's own tools (ociocheck, ocioconvert) run on the same pixels,
// and against published numbers: the sRGB curve (IEC 61966-2-1) and the
// Rec.709-to-ACEScg matrix.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/testing.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

// `command` with the shipped config as $OCIO; false when the tool is absent.
bool run_ocio_tool(const std::string& command, std::string* output) {
  const int rc = test::run_shell("OCIO=" LOOM_SHIPPED_OCIO " " + command, output);
  if (rc == 127) return false;
  EXPECT_EQ(rc, 0) << command << "\n" << *output;
  return true;
}

TEST(ColorConfig, OciocheckPassesTheShippedConfig) {
  std::string out;
  if (!run_ocio_tool("ociocheck --iconfig " LOOM_SHIPPED_OCIO, &out))
    GTEST_SKIP() << "ociocheck (opencolorio-tools) is not installed";
  EXPECT_NE(out.find("passed"), std::string::npos) << out;
  EXPECT_EQ(out.find("ERROR"), std::string::npos) << out;
  EXPECT_EQ(out.find("WARNING"), std::string::npos) << out;  // every role defined
  for (const char* view : {"(sRGB, Standard)", "(sRGB, ACES 1.0 - SDR Video)"})
    EXPECT_NE(out.find(view), std::string::npos) << view;
}

// A test image with values from 0 to 4 (over-range: scene-linear light),
// written as a float EXR by oiiotool (not by Loom).
fs::path test_exr(const fs::path& dir, std::string* out, double max = 4) {
  const fs::path file = dir / "in.exr";
  if (test::run_shell("oiiotool --pattern noise:type=uniform:min=0:max=" + std::to_string(max) +
                          ":seed=3 32x16 3 -d float -o " + file.string(),
                      out) != 0)
    return {};
  return file;
}

// Loads `file` (linear, as EXR holds it) and runs `convert`'s node on it.
Image convert(testing::Engine& e, const fs::path& file, const json& node) {
  testing::GraphBuilder g;
  g.node("load", "LoadImage").set("path", file.string());
  json doc = g.document();
  doc["nodes"]["convert"] = node;
  doc["nodes"]["convert"]["inputs"]["image"] = {{"from", "load.image"}};
  const testing::Run run = e.run(doc, {"convert.image"});
  EXPECT_TRUE(run.ok()) << run.errors();
  return run.ok() ? run.output<Image>("convert.image") : Image();
}

Image load(testing::Engine& e, const fs::path& file) {
  testing::GraphBuilder g;
  g.node("load", "LoadImage").set("path", file.string());
  return e.run(g, {"load.image"}).output<Image>("load.image");
}

// Largest difference relative to max(1, |reference|).
double relative_difference(const cv::Mat& a, const cv::Mat& reference) {
  cv::Mat scale = cv::max(cv::abs(reference), 1.0);
  cv::Mat d = cv::abs(a - reference) / scale;
  double worst = 0;
  cv::minMaxLoc(d.reshape(1), nullptr, &worst);
  return worst;
}

TEST(ColorConvert, EqualsOcioconvertOnTheSamePixels) {
  const fs::path dir = test::temp_dir();
  std::string out;
  const fs::path in = test_exr(dir, &out);
  if (in.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed: " << out;
  testing::Engine e;
  struct Case {
    const char* from;
    const char* to;
    Encoding tag;
  };
  for (const Case& c : {Case{"lin_rec709", "ACEScg", Encoding::linear}, Case{"ACEScg", "ACES2065-1", Encoding::linear},
                        Case{"lin_rec709", "srgb", Encoding::srgb}}) {
    const fs::path reference = dir / (std::string(c.to) + ".exr");
    if (!run_ocio_tool("ocioconvert " + in.string() + " " + c.from + " " + reference.string() + " " + c.to, &out))
      GTEST_SKIP() << "ocioconvert (opencolorio-tools) is not installed";
    const Image loom = convert(e, in, {{"type", "ColorConvert"}, {"inputs", {{"from", c.from}, {"to", c.to}}}});
    ASSERT_FALSE(loom.empty());
    EXPECT_EQ(loom.encoding, c.tag) << c.to;
    // ocioconvert's default processor takes fast pow/log approximations.
    EXPECT_LT(relative_difference(loom.pixels, load(e, reference).pixels), 1e-4) << c.from << " -> " << c.to;
  }
  const fs::path shown = dir / "aces_view.exr";
  if (!run_ocio_tool(
          "ocioconvert --view " + in.string() + " lin_rec709 " + shown.string() + " sRGB 'ACES 1.0 - SDR Video'", &out))
    GTEST_SKIP() << "ocioconvert (opencolorio-tools) is not installed";
  const Image view = convert(e, in, {{"type", "DisplayView"}, {"inputs", {{"view", "ACES 1.0 - SDR Video"}}}});
  EXPECT_EQ(view.encoding, Encoding::srgb);
  EXPECT_LT(relative_difference(view.pixels, load(e, shown).pixels), 1e-4);
}

TEST(ColorConvert, MatchesTheSrgbCurveAndTheAcescgMatrix) {
  testing::Engine e;
  const fs::path dir = test::temp_dir();
  std::string out;
  const fs::path in = test_exr(dir, &out);
  if (in.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed: " << out;
  const Image source = load(e, in);
  const Image srgb = convert(e, in, {{"type", "ColorConvert"}, {"inputs", {{"to", "srgb"}}}});
  const Image acescg = convert(e, in, {{"type", "ColorConvert"}, {"inputs", {{"to", "ACEScg"}}}});
  ASSERT_FALSE(srgb.empty() || acescg.empty());
  // Rec.709 → AP1 with Bradford adaptation (ACES TB-2014-004's matrix).
  const double m[3][3] = {
      {0.6130974, 0.3395231, 0.0473795}, {0.0701937, 0.9163539, 0.0134524}, {0.0206156, 0.1095698, 0.8698146}};
  double curve = 0, matrix = 0;
  for (int y = 0; y < source.height(); ++y)
    for (int x = 0; x < source.width(); ++x) {
      const auto& p = source.pixels.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double encoded = linear_to_srgb(p[c]);
        curve = std::max(curve, std::abs(srgb.pixels.at<cv::Vec3f>(y, x)[c] - encoded) / std::max(1.0, encoded));
        const double ap1 = m[c][0] * p[0] + m[c][1] * p[1] + m[c][2] * p[2];
        matrix = std::max(matrix, std::abs(acescg.pixels.at<cv::Vec3f>(y, x)[c] - ap1) / std::max(1.0, ap1));
      }
    }
  EXPECT_LT(curve, 1e-5);
  EXPECT_LT(matrix, 1e-5);  // the published matrix has 7 digits
}

// The Standard view is what SaveImage already does to a linear image for a
// PNG: the IEC sRGB curve (within the display range, where the display clips).
TEST(DisplayView, StandardIsTheSrgbCurveSaveImageApplies) {
  testing::Engine e;
  const fs::path dir = test::temp_dir();
  std::string out;
  const fs::path in = test_exr(dir, &out, 1.0);
  if (in.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed: " << out;
  const Image source = load(e, in);
  const Image shown = convert(e, in, {{"type", "DisplayView"}, {"inputs", {{"view", "Standard"}}}});
  ASSERT_FALSE(shown.empty());
  EXPECT_EQ(shown.encoding, Encoding::srgb);
  const Image encoded = with_encoding(source, Encoding::srgb);
  EXPECT_LT(cv::norm(shown.pixels, encoded.pixels, cv::NORM_INF), 1e-5);
}

TEST(ColorConvert, AnUnknownSpaceIsRefusedWhenTheGraphLoads) {
  testing::Engine e;
  testing::GraphBuilder g;
  g.node("board", "Checkerboard");
  g.node("convert", "ColorConvert").link("image", "board.image").set("to", "ACEScgg");
  try {
    e.load(g.document());
    FAIL() << "the graph was accepted";
  } catch (const GraphError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("/nodes/convert/inputs/to"), std::string::npos) << what;
    EXPECT_NE(what.find("did you mean \"ACEScg\""), std::string::npos) << what;
  }
}

TEST(ColorConvert, RefusesSpacesALoomImageCannotBeTaggedWith) {
  testing::Engine e;
  testing::GraphBuilder g;
  g.node("board", "Checkerboard");
  g.node("convert", "ColorConvert").link("image", "board.image").set("to", "ACEScct");
  const testing::Run run = e.run(g, {"convert.image"});
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.error("convert").find("\"ACEScct\" (encoding 'log')"), std::string::npos) << run.error("convert");
}

// `nodes` (a JSON object of nodes) after a LoadImage "load" of `file`; the run's `output`.
Image run_after_load(testing::Engine& e, const fs::path& file, const json& nodes, const std::string& output) {
  testing::GraphBuilder g;
  g.node("load", "LoadImage").set("path", file.string());
  json doc = g.document();
  doc["nodes"].update(nodes);
  const testing::Run run = e.run(doc, {output});
  EXPECT_TRUE(run.ok()) << run.errors();
  return run.ok() ? run.output<Image>(output) : Image();
}

// A converted image names its space, and the next node starts from it: two
// conversions in a row equal ocioconvert's one, and converting back to
// lin_rec709 leaves the image unnamed again (one description per image).
TEST(ColorConvert, TheConvertedImageCarriesItsSpaceToTheNextNode) {
  const fs::path dir = test::temp_dir();
  std::string out;
  const fs::path in = test_exr(dir, &out);
  if (in.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed: " << out;
  const fs::path reference = dir / "aces.exr";
  if (!run_ocio_tool("ocioconvert " + in.string() + " lin_rec709 " + reference.string() + " ACES2065-1", &out))
    GTEST_SKIP() << "ocioconvert (opencolorio-tools) is not installed";
  testing::Engine e;
  const json to_acescg = {{"type", "ColorConvert"},
                          {"inputs", {{"image", {{"from", "load.image"}}}, {"to", "ACEScg"}}}};
  const Image acescg = run_after_load(e, in, {{"cg", to_acescg}}, "cg.image");
  EXPECT_EQ(acescg.space, "ACEScg");
  EXPECT_EQ(acescg.encoding, Encoding::linear);
  const Image aces = run_after_load(
      e, in,
      {{"cg", to_acescg},
       {"ap0", {{"type", "ColorConvert"}, {"inputs", {{"image", {{"from", "cg.image"}}}, {"to", "ACES2065-1"}}}}}},
      "ap0.image");
  ASSERT_FALSE(aces.empty());
  EXPECT_EQ(aces.space, "ACES2065-1");
  EXPECT_LT(relative_difference(aces.pixels, load(e, reference).pixels), 1e-4);
  const Image back = run_after_load(
      e, in,
      {{"cg", to_acescg},
       {"back", {{"type", "ColorConvert"}, {"inputs", {{"image", {{"from", "cg.image"}}}, {"to", "lin_rec709"}}}}}},
      "back.image");
  EXPECT_EQ(back.space, "");
  EXPECT_LT(relative_difference(back.pixels, load(e, in).pixels), 1e-5);
  // DisplayView starts from the named space too: ocioconvert --view from ACEScg.
  const fs::path shown = dir / "shown.exr";
  ASSERT_TRUE(
      run_ocio_tool("ocioconvert " + in.string() + " lin_rec709 " + (dir / "cg.exr").string() + " ACEScg", &out));
  ASSERT_TRUE(run_ocio_tool(
      "ocioconvert --view " + (dir / "cg.exr").string() + " ACEScg " + shown.string() + " sRGB 'ACES 1.0 - SDR Video'",
      &out));
  const Image view = run_after_load(
      e, in,
      {{"cg", to_acescg},
       {"view",
        {{"type", "DisplayView"}, {"inputs", {{"image", {{"from", "cg.image"}}}, {"view", "ACES 1.0 - SDR Video"}}}}}},
      "view.image");
  EXPECT_EQ(view.encoding, Encoding::srgb);
  EXPECT_EQ(view.space, "");
  EXPECT_LT(relative_difference(view.pixels, load(e, shown).pixels), 1e-4);
}

// SaveImage writes the name into an EXR's header (oiiotool reads it there),
// LoadImage reads it back; an 8-bit file, which holds sRGB-encoded values,
// refuses the image rather than put ACEScg values through the sRGB curve.
TEST(ColorConvert, ANamedSpaceGoesThroughAnExrAndIsRefusedForAPng) {
  const fs::path dir = test::temp_dir();
  std::string out;
  const fs::path in = test_exr(dir, &out);
  if (in.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed: " << out;
  std::ofstream(dir / "g.json") << R"({"loom": 1, "nodes": {
    "load": {"type": "LoadImage", "inputs": {"path": ")" +
                                       in.string() + R"("}},
    "cg": {"type": "ColorConvert", "inputs": {"image": {"from": "load.image"}, "to": "ACEScg"}},
    "exr": {"type": "SaveImage", "inputs": {"image": {"from": "cg.image"}, "path": "cg.exr", "depth": "float"}},
    "layers": {"type": "SaveLayers", "inputs": {"image": {"from": "load.image"}, "albedo": {"from": "cg.image"},
                                                "path": "layers.exr"}},
    "png": {"type": "SaveImage", "inputs": {"image": {"from": "cg.image"}, "path": "cg.png"}}}})";
  const int rc = test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out);
  EXPECT_EQ(rc, 1) << out;  // the PNG fails, the EXRs are written
  EXPECT_NE(out.find("colour space ACEScg cannot be sRGB-encoded"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "out" / "cg.png"));
  std::string info;
  ASSERT_EQ(test::run_shell("oiiotool --info -v " + (dir / "out" / "cg.exr").string(), &info), 0) << info;
  EXPECT_NE(info.find("loom:colorspace: \"ACEScg\""), std::string::npos) << info;
  ASSERT_EQ(test::run_shell("oiiotool --info -v " + (dir / "out" / "layers.exr").string(), &info), 0) << info;
  EXPECT_NE(info.find("loom:colorspace.albedo: \"ACEScg\""), std::string::npos) << info;
  EXPECT_EQ(info.find("loom:colorspace.image"), std::string::npos) << info;  // lin_rec709: unnamed
  testing::Engine e;
  EXPECT_EQ(load(e, dir / "out" / "cg.exr").space, "ACEScg");
  testing::GraphBuilder g;
  g.node("albedo", "LoadImage").set("path", (dir / "out" / "layers.exr").string()).set("layer", "albedo");
  g.node("image", "LoadImage").set("path", (dir / "out" / "layers.exr").string()).set("layer", "image");
  const testing::Run run = e.run(g, {"albedo.image", "image.image"});
  ASSERT_TRUE(run.ok()) << run.errors();
  EXPECT_EQ(run.output<Image>("albedo.image").space, "ACEScg");
  EXPECT_EQ(run.output<Image>("image.image").space, "");
}

// $OCIO replaces Loom's config: its spaces become the choices, its
// scene_linear role the default; a config that cannot be read fails the
// colour nodes with the file and the reason, and nothing else.
TEST(ColorConfig, OcioNamesAStudioConfigAndABadOneFailsOnlyTheColourNodes) {
  const fs::path dir = test::temp_dir();
  std::string config = test::read_text(LOOM_SHIPPED_OCIO);
  ASSERT_FALSE(config.empty());
  for (std::size_t at; (at = config.find("lin_rec709")) != std::string::npos;)
    config.replace(at, 10, "Linear Rec.709 (sRGB)");
  std::ofstream(dir / "studio.ocio") << config;
  std::string out;
  ASSERT_EQ(test::run_loom_env("OCIO=" + (dir / "studio.ocio").string(), "nodes ColorConvert", &out), 0) << out;
  EXPECT_NE(out.find("to: Enum = \"Linear Rec.709 (sRGB)\""), std::string::npos) << out;
  EXPECT_EQ(out.find("| lin_rec709 |"), std::string::npos) << out;  // not a choice: the studio names it otherwise
  std::ofstream(dir / "g.json") << R"({"loom": 1, "nodes": {
    "board": {"type": "Checkerboard", "inputs": {"size": [8, 8]}},
    "convert": {"type": "ColorConvert", "inputs": {"image": {"from": "board.image"}, "to": "srgb"}},
    "save": {"type": "SaveImage", "inputs": {"image": {"from": "convert.image"}, "path": "c.png"}},
    "plain": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "b.png"}}}})";
  const int rc = test::run_loom_env("OCIO=" + (dir / "missing.ocio").string(),
                                    "run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out);
  EXPECT_EQ(rc, 1) << out;  // a node failed; the graph loaded
  EXPECT_NE(out.find("missing.ocio ($OCIO)"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "b.png"));
  EXPECT_FALSE(fs::exists(dir / "out" / "c.png"));
}

}  // namespace
}  // namespace loom
