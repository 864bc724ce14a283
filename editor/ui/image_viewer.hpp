// The image viewer: zoom (wheel) and pan (right or middle drag), a pixel
// inspector with values in the image's own encoding, channel toggles, and
// exposure for linear images (shown sRGB-encoded, as SaveImage would write
// them). The left mouse button is left to the interactive tools, which get
// the image-to-screen mapping through ImageView.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <cstdint>

#include <imgui.h>

#include "loom/image.hpp"

namespace loom::editor {

// Image pixel coordinates (origin top-left, y down, pixel centres at +0.5)
// to screen pixels and back.
struct ImageView {
  ImVec2 origin{0, 0};
  float scale = 1;
  int width = 0, height = 0;  // the image's, in pixels
  bool hovered = false;
  bool active = false;  // a mouse button went down on the image and is held
  ImVec2 to_screen(double x, double y) const {
    return {origin.x + float(x) * scale, origin.y + float(y) * scale};
  }
  ImVec2 to_image(ImVec2 s) const { return {(s.x - origin.x) / scale, (s.y - origin.y) / scale}; }
};

class ImageViewer {
 public:
  ImageViewer() = default;
  ~ImageViewer();
  ImageViewer(const ImageViewer&) = delete;
  ImageViewer& operator=(const ImageViewer&) = delete;

  // Draws the image into the remaining content region; a new image of
  // another size is fitted. With `navigate` false the wheel and the right
  // and middle drags are left to the caller (the viewport camera) instead of
  // zooming and panning the image.
  ImageView draw(const Image& image, const void* identity, bool navigate = true);
  void fit() { fit_ = true; }
  int uploads() const { return uploads_; }  // textures made so far (tests)

  // A display's views (the colour plugin's DisplayView): a linear RGB(A)
  // image may be shown through one of them, its exposure applied first,
  // instead of through the sRGB curve. `apply` returns the display-encoded
  // image (it may throw: the viewer then says why and uses the curve). An
  // image in a named colour space is shown through a view even with the curve
  // chosen: `view` is then "", the display's default view.
  using ViewTransform = std::function<Image(const Image& linear, const std::string& view)>;
  void set_views(std::vector<std::string> views, ViewTransform apply);
  const std::vector<std::string>& views() const { return views_; }
  // "" (the sRGB curve) or one of views(), as the "view" menu sets it.
  void choose_view(const std::string& view);

 private:
  void toolbar(const Image& image);
  void upload(const Image& image);
  bool shows_through_view(const Image& image) const;
  Image through_view(const Image& image);
  ImageView place(ImVec2 origin, ImVec2 size, bool navigate);
  void inspect(const Image& image, const ImageView& view, bool navigate) const;
  int uploads_ = 0;
  unsigned texture_ = 0;
  const void* uploaded_ = nullptr;
  float uploaded_exposure_ = 0;
  bool uploaded_channels_[4] = {true, true, true, true};
  int width_ = 0, height_ = 0;
  float exposure_ = 0;
  std::vector<std::string> views_;
  ViewTransform apply_view_;
  std::string view_, uploaded_view_, view_error_;
  bool channels_[4] = {true, true, true, true};
  float zoom_ = 1;
  ImVec2 pan_{0, 0};
  bool fit_ = true;
};

}  // namespace loom::editor
