// Issue 41 in the window (1600x900 under Xvfb): a PathTrace of the Cornell
// box refines on screen pass by pass; an edit upstream (the camera) cancels it
// and the first pass of the new render is on screen fast; a drag on the image
// orbits the camera as one undo step; ARAP's map refines; and what the viewer
// shows of a linear image through a view of the colour config (issue 40).
// Prints the figures docs/editor.md reports: edit -> first new pixels on
// screen, and updates per second.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "loom/call_node.hpp"
#include "loom/image.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The Cornell box seen through a Camera node (CornellBox's own camera:
// eye 278 273 -800, looking along +z), path traced at size x size.
json cornell_with_camera(int size, int spp) {
  return {{"loom", 1},
          {"seed", 13},
          {"nodes",
           {{"box", {{"type", "CornellBox"}}},
            {"camera", {{"type", "Camera"},
                        {"inputs", {{"eye", {278, 273, -800}}, {"target", {278, 273, 0}}, {"fov_degrees", 39.3}}}}},
            {"scene",
             {{"type", "MergeScenes"}, {"inputs", {{"a", {{"from", "box.scene"}}}, {"b", {{"from", "camera.scene"}}}}}}},
            {"trace", {{"type", "PathTrace"},
                       {"inputs", {{"scene", {{"from", "scene.scene"}}}, {"size", {size, size}}, {"spp", spp}}}}}}}};
}

// Frames until the viewer shows a pass (or the result) of the document's
// current revision; the seconds it took, or a negative number on timeout.
double until_shown(Harness& h, double timeout = 30) {
  const auto start = Clock::now();
  while (h.app.shown_revision() != h.app.document().revision() || h.app.image_viewer().uploads() == 0) {
    if (since(start) > timeout) return -1;
    h.frame();
  }
  return since(start);
}

TEST(EditorProgressive, PassesRefineOnScreenAndAnEditShowsTheNewRenderFast) {
  Harness h(1600, 900);
  h.app.open(write_graph(cornell_with_camera(512, 1 << 16), "cornell.json"));
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "trace"));
  ASSERT_EQ(h.app.state().viewed, "trace");
  ASSERT_GT(until_shown(h, 60), 0) << "no pass shown";

  // Updates per second while it refines: textures of new passes per second.
  const int before = h.app.image_viewer().uploads();
  const auto watch = Clock::now();
  while (since(watch) < 3) h.frame();
  const double updates = (h.app.image_viewer().uploads() - before) / since(watch);

  // Edit -> first new pixels on screen: the camera moved in the graph (as the
  // property panel writes it), then frames until the viewer drew a pass of
  // the new revision (the frame is swapped when h.frame() returns).
  std::vector<double> latencies;
  GraphDocument& doc = h.app.document();
  for (int k = 1; k <= 5; ++k) {
    doc.set_input("camera", "eye", json::array({278 + 20 * k, 273, -800}));
    latencies.push_back(until_shown(h));
    ASSERT_GT(latencies.back(), 0) << "edit " << k << " never shown";
    h.frame(3);
  }
  std::sort(latencies.begin(), latencies.end());
  std::printf("PathTrace 512x512 in the editor: edit -> first new pixels %.0f ms (median of 5; %.0f..%.0f), "
              "%.1f updates/s while refining\n",
              latencies[2] * 1e3, latencies.front() * 1e3, latencies.back() * 1e3, updates);
  // Partials come at least 0.08 s apart inside long passes (10-12 a second
  // quiet); half the target leaves room for a loaded machine. Passes alone
  // gave 2.0-2.3 a second.
  EXPECT_GE(updates, 5.0);

  // A left drag on the image orbits: the camera's eye moves, one undo step.
  const json eye = doc.literal("camera", "eye");
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0);
  const ImVec2 centre = view.to_screen(256, 256);
  h.drag(centre, ImVec2(centre.x + 120, centre.y + 30));
  EXPECT_NE(doc.literal("camera", "eye"), eye);
  ASSERT_GT(until_shown(h), 0);
  h.frame(10);
  h.screenshot("progressive-pathtrace");
  doc.undo();
  EXPECT_EQ(doc.literal("camera", "eye"), eye);
}

// The shipped graph, as a new user opens it: the blocks' render refines on
// screen and a drag on it orbits the graph's own Camera node.
TEST(EditorProgressive, TheShippedCornellGraphOrbitsWithTheMouse) {
  Harness h(1600, 900);
  const auto opened = Clock::now();
  h.app.open(std::filesystem::path(LOOM_SOURCE_DIR) / "graphs" / "pathtrace-cornell-box.json");
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "trace"));
  ASSERT_EQ(h.app.state().viewed, "trace");
  ASSERT_GT(until_shown(h, 60), 0) << "no pass shown";
  std::printf("graphs/pathtrace-cornell-box.json: opened -> first pixels of trace on screen %.0f ms\n",
              since(opened) * 1e3);
  GraphDocument& doc = h.app.document();
  const json eye = doc.literal("camera", "eye");
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0);
  const ImVec2 centre = view.to_screen(128, 128);
  h.drag(centre, ImVec2(centre.x - 100, centre.y + 20));
  EXPECT_NE(doc.literal("camera", "eye"), eye);
  ASSERT_GT(until_shown(h), 0) << "the orbited render never shown";
  h.frame(30);
  h.screenshot("cornell-graph-orbited");
}

// ARAP publishes its map as it iterates: the viewer shows the mesh refining
// (maps of rising iterations, "refining: k/400 iterations") before the result comes.
TEST(EditorProgressive, ArapsMapRefinesInTheViewer) {
  Harness h(1600, 900);
  h.app.open(write_graph(
      {{"loom", 1},
       {"nodes",
        {{"hemi", {{"type", "HemisphereMesh"}, {"inputs", {{"rings", 60}, {"segments", 240}, {"noise", 0.1}}}}},
         {"arap",
          {{"type", "ARAP"},
           {"inputs",
            {{"mesh", {{"from", "hemi.mesh"}}}, {"init", "tutte"}, {"iterations", 400}, {"tolerance", 0}}}}}}}},
      "arap.json"));
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "arap"));
  ASSERT_EQ(h.app.state().viewed, "arap");
  std::vector<double> shown;  // iterations of the maps the viewer showed
  for (const auto start = Clock::now(); since(start) < 30 && h.app.controller().busy();) {
    h.frame();
    const auto p = h.app.controller().partial("arap", "mesh");
    if (p && (shown.empty() || shown.back() != p->done)) shown.push_back(p->done);
    if (shown.size() == 3) h.screenshot("arap-refining");
  }
  ASSERT_GE(shown.size(), 2u) << "no map shown while ARAP iterated";
  EXPECT_TRUE(std::is_sorted(shown.begin(), shown.end()));
  std::printf("ARAP 14,400 vertices in the editor: %zu maps shown while iterating (iterations %.0f..%.0f)\n",
              shown.size(), shown.front(), shown.back());
}

// A 64² board of one sRGB colour converted to colour space `to`, opened and
// viewed: the image the viewer shows (empty when nothing was shown).
Value view_converted(Harness& h, const cv::Vec3f& srgb, const std::string& to, const std::string& file) {
  h.app.open(write_graph(
      {{"loom", 1},
       {"nodes",
        {{"board",
          {{"type", "Checkerboard"},
           {"inputs", {{"size", {64, 64}}, {"cells", 1}, {"color_a", {srgb[0], srgb[1], srgb[2], 1}}}}}},
         {"convert", {{"type", "ColorConvert"}, {"inputs", {{"image", {{"from", "board.image"}}}, {"to", to}}}}}}}},
      file));
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "convert"));
  if (until_shown(h) <= 0) return {};
  const Value shown = h.app.state().viewed_output(0);
  return shown && shown.is<Image>() ? shown : Value();
}

// The viewer shows a linear image through a view of the colour config when
// asked (the "view" menu): the pixels on screen are the DisplayView node's
// for that image, and the sRGB curve's again when the menu says so.
TEST(EditorViewer, ALinearImageIsShownThroughTheChosenView) {
  Harness h(1600, 900);
  if (h.app.image_viewer().views().empty()) GTEST_SKIP() << "plugin color (OpenColorIO) not built";
  const Value shown = view_converted(h, {0.6f, 0.5f, 0.4f}, "lin_rec709", "view.json");
  ASSERT_TRUE(shown);
  const ImVec2 centre = h.app.image_view().to_screen(32, 32);
  const auto screen = [&](const std::string& name) {
    h.frame(3);
    const Rgba8Image frame = h.screenshot(name);
    const std::uint8_t* p = frame.at(int(centre.x), int(centre.y));
    return std::vector<int>{p[0], p[1], p[2]};
  };
  const auto bytes = [](const cv::Vec3f& v) {
    std::vector<int> out;
    for (int k = 0; k < 3; ++k) out.push_back(int(std::clamp(v[k], 0.0f, 1.0f) * 255.0f + 0.5f));
    return out;
  };
  const cv::Vec3f linear = shown.as<Image>().pixels.at<cv::Vec3f>(32, 32);
  const cv::Vec3f curve(linear_to_srgb(linear[0]), linear_to_srgb(linear[1]), linear_to_srgb(linear[2]));
  EXPECT_EQ(screen("viewer-srgb-curve"), bytes(curve));

  h.app.image_viewer().choose_view("ACES 1.0 - SDR Video");
  NodeCall call;
  call.values.emplace("image", shown);
  call.literals["view"] = "ACES 1.0 - SDR Video";
  const Image by_node = call_node(*h.app.registry().find("DisplayView"), call).at(0).as<Image>();
  const std::vector<int> aces = screen("viewer-aces-view");
  EXPECT_EQ(aces, bytes(by_node.pixels.at<cv::Vec3f>(32, 32)));
  h.app.image_viewer().choose_view("");
  EXPECT_NE(screen("viewer-srgb-curve"), aces);  // the filmic curve darkens mid-grey where the sRGB curve does not
}

// An image that names its colour space (ACEScg) is shown through the
// display's default view even with the sRGB curve chosen: on screen, the
// sRGB colour it was converted from, not the curve applied to AP1 values.
TEST(EditorViewer, AnImageInANamedSpaceIsShownAsItsColours) {
  Harness h(1600, 900);
  if (h.app.image_viewer().views().empty()) GTEST_SKIP() << "plugin color (OpenColorIO) not built";
  const cv::Vec3f srgb(0.6f, 0.3f, 0.1f);  // Checkerboard's colours are sRGB-encoded
  const Value shown = view_converted(h, srgb, "ACEScg", "named.json");
  ASSERT_TRUE(shown);
  EXPECT_EQ(shown.as<Image>().space, "ACEScg");
  const cv::Vec3f ap1 = shown.as<Image>().pixels.at<cv::Vec3f>(32, 32);
  const cv::Vec3f linear(srgb_to_linear(srgb[0]), srgb_to_linear(srgb[1]), srgb_to_linear(srgb[2]));
  ASSERT_GT(cv::norm(ap1 - linear), 0.05);  // AP1 values differ from the Rec.709 ones
  h.frame(3);
  const ImVec2 centre = h.app.image_view().to_screen(32, 32);
  const Rgba8Image frame = h.screenshot("viewer-named-space");
  const std::uint8_t* p = frame.at(int(centre.x), int(centre.y));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], srgb[k] * 255.0f + 0.5f, 1.0) << "channel " << k;
}

}  // namespace
}  // namespace loom::editor::test
