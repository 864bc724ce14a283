// The viewer of a rendered image (a node with a "scene" input and an Image
// output: Render, PathTrace).
//
// Refining: while such a node publishes partial images (PathTrace after each
// pass, Context::publish_partial), the newest pass replaces the finished
// image of the previous evaluation, with "N/M spp, T s, ±E %" — E the
// estimated relative error of the mean so far — until the new evaluation
// finishes.
//
// Camera: with "camera" on, a left drag on the image orbits, a right or
// middle drag pans and the wheel dollies the scene's camera, by writing the
// eye and target of the Camera node that feeds the scene (one undo step per
// drag). Without a Camera node upstream the viewer says so.
#pragma once

#include <optional>
#include <string>

#include "editor_state.hpp"
#include "image_viewer.hpp"
#include "model/viewport_camera.hpp"

namespace loom::editor {

class RenderViewport {
 public:
  // Whether node `id` renders a scene (a "scene" input and an Image output).
  static bool applies(const EditorState& state, const std::string& id);
  // The newest partial value of id.output, of the evaluation shown or a
  // newer one (none: the node published none since).
  static std::optional<Partial> newest_pass(const EditorState& state, const EvaluationController& controller,
                                            const std::string& id, const std::string& output);
  // Whether it is newer than the evaluation shown: it stands in for the result.
  static bool refining(const EditorState& state, const Partial& p) {
    return !state.eval || p.revision > state.eval->revision;
  }
  // "16/64 spp, 0.42 s, ±3.1 %"
  static std::string status(const Partial& p);

  // The "camera" toggle, or why the mouse cannot move the camera (with an
  // "add a Camera node" button, initialised from the scene's own camera,
  // when none feeds it). Returns whether the mouse moves it (the image
  // viewer then leaves the mouse to draw()).
  bool toolbar(EditorState& state, const std::string& id);
  // Turns the drag or the wheel over the image into a camera edit.
  void draw(EditorState& state, const std::string& id, const ImageView& view);

 private:
  static void add_camera_from_scene(EditorState& state, const std::string& id);
  bool enabled_ = true;
  std::optional<std::string> camera_;  // found by toolbar() this frame
  std::optional<LookAt> look_;
  bool dragging_ = false;
};

}  // namespace loom::editor
