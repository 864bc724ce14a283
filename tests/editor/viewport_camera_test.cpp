// The viewport camera's moves, checked by what each must keep (orbit: the
// distance to the target and the target; pan: the view direction and the
// distance; dolly: the direction), the Camera node found upstream of a
// renderer, and one drag written as one undo step.
#include <cmath>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "model/viewport_camera.hpp"

namespace loom::editor {
namespace {

const LookAt kStart{Vec3(1, 2, 6), Vec3(0, 0.5, 0), Vec3(0, 1, 0), 40};

TEST(ViewportCamera, OrbitKeepsTheTargetAndTheDistanceAndTurnsByTheAngle) {
  const LookAt c = orbit(kStart, 0.3, 0);
  EXPECT_EQ(c.target, kStart.target);
  EXPECT_NEAR((c.eye - c.target).norm(), (kStart.eye - kStart.target).norm(), 1e-12);
  // Yaw turns about up: the height stays, the horizontal angle changes by 0.3.
  EXPECT_NEAR(c.eye.y(), kStart.eye.y(), 1e-12);
  const Vec3 a = kStart.eye - kStart.target, b = c.eye - c.target;
  const double turned = std::atan2(a.z(), a.x()) - std::atan2(b.z(), b.x());
  EXPECT_NEAR(std::remainder(turned, 2 * M_PI), -0.3, 1e-12);
  // Pitch raises the eye, and stops short of the pole.
  const LookAt up = orbit(kStart, 0, 0.2);
  EXPECT_GT(up.eye.y(), kStart.eye.y());
  EXPECT_NEAR((up.eye - up.target).norm(), (kStart.eye - kStart.target).norm(), 1e-12);
  const LookAt over = orbit(kStart, 0, 10);
  const Vec3 v = (over.eye - over.target).normalized();
  EXPECT_LT(v.dot(Vec3(0, 1, 0)), 1 - 1e-5);
  EXPECT_GT(v.dot(Vec3(0, 1, 0)), std::cos(2 * M_PI / 180));
}

TEST(ViewportCamera, PanMovesEyeAndTargetTogetherAcrossTheView) {
  const LookAt c = pan(kStart, 0.25, -0.1);
  const Vec3 move = c.eye - kStart.eye;
  EXPECT_NEAR((c.target - kStart.target - move).norm(), 0, 1e-12);
  EXPECT_NEAR(move.dot((kStart.target - kStart.eye).normalized()), 0, 1e-12);  // in the image plane
  // A quarter of the view's height at the target: 0.25 * 2 d tan(20°), with 0.1 of it up or down.
  const double height = 2 * (kStart.target - kStart.eye).norm() * std::tan(20 * M_PI / 180);
  EXPECT_NEAR(move.norm(), std::hypot(0.25, 0.1) * height, 1e-9);
  EXPECT_LT(move.x(), 0);  // the scene moves right: the camera left
}

TEST(ViewportCamera, DollyScalesTheDistanceAlongTheView) {
  const LookAt c = dolly(kStart, 0.5);
  EXPECT_EQ(c.target, kStart.target);
  EXPECT_NEAR((c.eye - c.target).norm(), 0.5 * (kStart.eye - kStart.target).norm(), 1e-12);
  EXPECT_NEAR((c.eye - c.target).normalized().dot((kStart.eye - kStart.target).normalized()), 1, 1e-12);
}

TEST(ViewportCamera, TheCameraUpstreamOfARendererIsWrittenAsOneUndoStepPerDrag) {
  testing::Engine engine;
  engine.load_plugins({"Camera", "MergeScenes", "CornellBox", "PathTrace"});
  GraphDocument doc(engine.registry());
  doc.load_json(json::parse(R"({"loom": 1, "nodes": {
    "box": {"type": "CornellBox"},
    "cam": {"type": "Camera", "inputs": {"eye": [278, 273, -800], "target": [278, 273, 0]}},
    "scene": {"type": "MergeScenes", "inputs": {"a": {"from": "box.scene"}, "b": {"from": "cam.scene"}}},
    "trace": {"type": "PathTrace", "inputs": {"scene": {"from": "scene.scene"}}},
    "bare": {"type": "PathTrace", "inputs": {"scene": {"from": "box.scene"}}}}})"));
  EXPECT_EQ(camera_feeding(doc, "trace"), "cam");
  EXPECT_FALSE(camera_feeding(doc, "bare"));  // CornellBox's own camera is no node
  const auto look = camera_inputs(doc, "cam");
  ASSERT_TRUE(look);
  EXPECT_EQ(look->eye, Vec3(278, 273, -800));
  EXPECT_EQ(look->up, Vec3(0, 1, 0));  // the default
  EXPECT_EQ(look->fov_degrees, 45);
  const json before = doc.document();
  LookAt c = *look;
  for (int step = 0; step < 5; ++step) {  // a drag: five mouse moves
    c = orbit(c, 0.05, 0.02);
    write_camera(doc, "cam", c, "viewport-drag");
  }
  doc.end_merge();
  EXPECT_NEAR(doc.literal("cam", "eye")[0].get<double>(), c.eye.x(), 1e-9);
  ASSERT_TRUE(doc.undo());
  EXPECT_EQ(doc.document(), before);  // the whole drag, undone at once

  // A renderer without a Camera node is given one, merged over its scene;
  // the graph stays valid and the mouse can then move it.
  const std::string added = add_camera(doc, "bare", kStart);
  EXPECT_EQ(camera_feeding(doc, "bare"), added);
  ASSERT_TRUE(camera_inputs(doc, added));
  EXPECT_EQ(camera_inputs(doc, added)->eye, kStart.eye);
  EXPECT_EQ(doc.link(doc.link("bare", "scene")->node, "a")->node, "box");
  EXPECT_NO_THROW(engine.load(doc.document()));
}

}  // namespace
}  // namespace loom::editor
