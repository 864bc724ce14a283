// The time slider under Xvfb: the graph reopens at the frame in its "ui"
// field, scrubbing by dragging on the bar evaluates that frame and the viewer
// shows that frame's image, the simulation's stepped frames are marked on the
// bar, playback moves on and loops, and an edit upstream of the simulation
// drops its marks.
#include <fstream>

#include "loom/image.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;

// Frames 1..12: a checkerboard with as many cells as the frame number, and
// a simulation x(f) = x(f-1) + v / fps from x0.
json timed_graph() {
  return {{"loom", 1},
          {"time", {{"start", 1}, {"end", 12}, {"fps", 24}}},
          {"ui", {{"frame", 3}}},
          {"nodes",
           {{"time", {{"type", "Time"}, {"ui", {{"pos", {0, 0}}}}}},
            {"board",
             {{"type", "Checkerboard"},
              {"inputs", {{"size", {240, 240}}, {"cells", {{"from", "time.frame"}}}}},
              {"ui", {{"pos", {260, 0}}}}}},
            {"x0", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 0}}}, {"ui", {{"pos", {0, 220}}}}}},
            {"sim",
             {{"type", "Integrate"},
              {"inputs", {{"x", {{"from", "x0.result"}}}, {"v", 2}, {"ms", 5}}},
              {"ui", {{"pos", {260, 220}}}}}}}}};
}

std::vector<int> span(int first, int last) {
  std::vector<int> v;
  for (int f = first; f <= last; ++f) v.push_back(f);
  return v;
}

// Whether the checkerboard of `frame` cells has its corner colour at (x, y).
bool corner_colour(int frame, double x, double y) {
  const double cell = 240.0 / frame;
  return (int(x / cell) + int(y / cell)) % 2 == 0;
}

// The viewed image is the checkerboard of `frame`, in the engine's value and
// on screen where the viewer drew it; returns how many of the sampled
// points would show the other colour at `other_frame`.
int expect_board_of_frame(Harness& h, int frame, int other_frame) {
  const Value v = h.app.state().viewed_output(0);
  EXPECT_TRUE(v && v.is<Image>());
  if (!v || !v.is<Image>()) return 0;
  const cv::Mat& m = v.as<Image>().pixels;
  const Rgba8Image shot = h.screenshot("timeline-frame-" + std::to_string(frame));
  const ImageView view = h.app.image_view();
  EXPECT_GT(view.scale, 0);
  int differing = 0;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const double x = 20 + 40 * i + 7, y = 20 + 40 * j + 3;
      const bool a = corner_colour(frame, x, y);
      // The engine's image: color_a is light grey (0.95), color_b blue (0.15, 0.3, 0.6).
      EXPECT_NEAR(m.at<cv::Vec3f>(int(y), int(x))[0], a ? 0.95f : 0.15f, 1e-6) << x << "," << y;
      // The screen: the red channel tells them apart.
      const ImVec2 s = view.to_screen(x + 0.5, y + 0.5);
      const std::uint8_t red = shot.at(int(s.x), int(s.y))[0];
      EXPECT_EQ(red > 150, a) << "frame " << frame << " at image " << x << "," << y << ": red " << int(red);
      differing += corner_colour(other_frame, x, y) != a;
    }
  return differing;
}

TEST(EditorTimeline, ScrubPlayAndMarksDroppedByAnUpstreamEdit) {
  Harness h(1400, 820, /*test_plugins=*/true);
  const fs::path file = loom::test::temp_dir() / "timeline.json";
  std::ofstream(file) << timed_graph().dump(1);
  h.app.open(file);
  ASSERT_TRUE(h.settle());
  auto& state = h.app.state();
  GraphDocument& doc = h.app.document();
  Timeline& timeline = h.app.timeline();
  EXPECT_EQ(doc.frame(), 3);  // reopened where it was saved
  EXPECT_EQ(state.eval->frame, 3);
  ASSERT_GT(timeline.bar_max().x, timeline.bar_min().x + 100);  // shown: the graph has frames

  h.click(h.app.canvas().node_header(state, "board"));
  ASSERT_TRUE(h.settle());
  ASSERT_EQ(state.viewed, "board");
  EXPECT_GT(expect_board_of_frame(h, 3, 8), 5);

  // Scrub: drag the handle from frame 3 to frame 8.
  h.drag(timeline.frame_position(3), timeline.frame_position(8), 0, 10);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(doc.frame(), 8);
  EXPECT_EQ(state.eval->frame, 8);
  EXPECT_GT(expect_board_of_frame(h, 8, 3), 5);  // the viewer shows frame 8's image, not 3's
  EXPECT_FALSE(doc.dirty());                      // moving the slider is not an edit

  // View the simulation: the frames it stepped to reach 8 are marked.
  h.click(h.app.canvas().node_header(state, "sim"));
  ASSERT_TRUE(h.settle());
  ASSERT_EQ(state.viewed, "sim");
  EXPECT_EQ(timeline.marks(state), span(1, 8));
  EXPECT_NEAR(state.viewed_output(0).as<double>(), 1 + 2 * 7 / 24.0, 1e-12);
  Rgba8Image shot = h.screenshot("timeline-marks");
  auto mark_at = [&](int frame) {
    const ImVec2 p = timeline.frame_position(frame);
    const std::uint8_t* px = shot.at(int(p.x), int(timeline.bar_max().y) - 2);
    return px[2] > 200 && px[0] < 100;  // the marks' blue
  };
  EXPECT_TRUE(mark_at(2));
  EXPECT_TRUE(mark_at(6));
  EXPECT_FALSE(mark_at(11));

  // Play: frames move on as they are computed, to the end, then loop.
  int frame = doc.frame();
  timeline.playback().play(glfwGetTime(), *doc.time_range(), frame);
  std::vector<int> seen{doc.frame()};
  for (int i = 0; i < 2000 && seen.size() < 8; ++i) {
    h.frame();
    if (doc.frame() != seen.back()) seen.push_back(doc.frame());
  }
  EXPECT_EQ(seen, (std::vector<int>{8, 9, 10, 11, 12, 1, 2, 3}));
  timeline.playback().pause();
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(timeline.marks(state), span(1, 12));

  // Back to frame 2 (a cache hit), then edit the initial state upstream of
  // the simulation: every frame after the one shown loses its mark.
  h.drag(timeline.frame_position(doc.frame()), timeline.frame_position(2), 0, 6);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.eval->result.nodes.at("sim").status, NodeStatus::cached);
  EXPECT_EQ(timeline.marks(state), span(1, 12));
  doc.set_input("x0", "a", 5.0);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(timeline.marks(state), span(1, 2));
  EXPECT_NEAR(state.viewed_output(0).as<double>(), 5 + 2 * 1 / 24.0, 1e-12);
  shot = h.screenshot("timeline-marks-dropped");
  EXPECT_TRUE(mark_at(1));  // (frame 2 is under the handle)
  EXPECT_FALSE(mark_at(6));

  // Saved with the frame in "ui"; the file is still a runnable graph.
  h.app.save(file);
  std::ifstream in(file);
  const json saved = json::parse(in);
  EXPECT_EQ(saved["ui"], (json{{"frame", 2}}));
  EXPECT_NO_THROW(parse_graph(saved, file));
}

}  // namespace
}  // namespace loom::editor::test
