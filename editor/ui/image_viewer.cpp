#include "image_viewer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <GL/gl.h>
#include <opencv2/core.hpp>

namespace loom::editor {

ImageViewer::~ImageViewer() {
  if (texture_) glDeleteTextures(1, &texture_);
}

void ImageViewer::set_views(std::vector<std::string> views, ViewTransform apply) {
  views_ = std::move(views);
  apply_view_ = std::move(apply);
  if (std::find(views_.begin(), views_.end(), view_) == views_.end()) view_.clear();
}

void ImageViewer::choose_view(const std::string& view) {
  if (view.empty() || std::find(views_.begin(), views_.end(), view) != views_.end()) view_ = view;
}

// An image in a named colour space (ACEScg) goes through the display's
// default view even when the sRGB curve is chosen: the curve alone would show
// its values as if they were Rec.709's.
bool ImageViewer::shows_through_view(const Image& image) const {
  return (!view_.empty() || !image.space.empty()) && apply_view_ && image.encoding == Encoding::linear &&
         (image.channels() == 3 || image.channels() == 4);
}

// The image through the chosen view, its exposure applied first (scene
// light scaled, as a camera's exposure does); alpha is left as it is.
Image ImageViewer::through_view(const Image& image) {
  const double gain = std::exp2(double(exposure_));
  cv::Mat exposed;
  cv::multiply(image.pixels, cv::Scalar(gain, gain, gain, 1.0), exposed);
  return apply_view_(image.like(exposed), view_);
}

void ImageViewer::upload(const Image& image) {
  // Through a view: its display-encoded result is shown as it is.
  Image viewed;
  bool view = shows_through_view(image);
  if (view) {
    try {
      viewed = through_view(image);
      view_error_.clear();
    } catch (const std::exception& e) {
      view_error_ = e.what();
      view = false;
    }
  }
  const Image& shown = view ? viewed : image;
  const int w = shown.width(), h = shown.height(), c = shown.channels();
  const bool linear = shown.encoding == Encoding::linear;
  const float gain = std::exp2(exposure_);
  // Which channels are on: a single one is shown as gray.
  int only = -1, on = 0;
  for (int k = 0; k < std::min(c, 4); ++k)
    if (channels_[k]) {
      only = k;
      ++on;
    }
  std::vector<std::uint8_t> rgba(std::size_t(w) * h * 4);
  auto encode = [&](float v, bool alpha) {
    if (!std::isfinite(v)) v = 0;
    if (!alpha && linear) v = linear_to_srgb(std::max(0.0f, v * gain));
    return std::uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
  };
  for (int y = 0; y < h; ++y) {
    const float* row = shown.pixels.ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      const float* px = row + std::size_t(x) * c;
      std::uint8_t* out = &rgba[(std::size_t(y) * w + x) * 4];
      const bool has_alpha = c == 2 || c == 4;
      if (on == 1) {
        const std::uint8_t g = encode(px[only], has_alpha && only == c - 1);
        out[0] = out[1] = out[2] = g;
      } else if (c <= 2) {
        out[0] = out[1] = out[2] = channels_[0] ? encode(px[0], false) : 0;
      } else {
        for (int k = 0; k < 3; ++k) out[k] = channels_[k] ? encode(px[k], false) : 0;
      }
      out[3] = 255;
    }
  }
  if (!texture_) glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
}

void ImageViewer::toolbar(const Image& image) {
  const int c = image.channels();
  const bool linear = image.encoding == Encoding::linear;
  static const char* names[4] = {"R", "G", "B", "A"};
  const char* gray_names[2] = {"Y", "A"};
  for (int k = 0; k < std::min(c, 4); ++k) {
    if (k) ImGui::SameLine();
    ImGui::Checkbox(c <= 2 ? gray_names[k] : names[k], &channels_[k]);
  }
  if (linear) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(120);
    ImGui::SliderFloat("exposure", &exposure_, -8, 8, "%+.1f EV");
  }
  if (linear && (c == 3 || c == 4) && !views_.empty()) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(190);
    // An image naming its space is never shown through the curve alone: the
    // first choice is then the display's default view.
    const char* first = image.space.empty() ? "sRGB curve" : "default view";
    if (ImGui::BeginCombo("view", view_.empty() ? first : view_.c_str())) {
      if (ImGui::Selectable(first, view_.empty())) view_.clear();
      for (const std::string& v : views_)
        if (ImGui::Selectable(v.c_str(), v == view_)) view_ = v;
      ImGui::EndCombo();
    }
    if (!view_error_.empty()) {
      ImGui::SameLine();
      ImGui::TextDisabled("view failed: %s", view_error_.c_str());
    }
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("fit")) fit_ = true;
  ImGui::SameLine();
  ImGui::TextDisabled("%dx%dx%d %s", image.width(), image.height(), c, describe_space(image).c_str());
}

// The image's place in the region at `origin`: fitted, or zoomed by the
// wheel about the cursor and panned by a right or middle drag.
ImageView ImageViewer::place(ImVec2 origin, ImVec2 size, bool navigate) {
  if (fit_) {
    zoom_ = std::min(size.x / float(width_), size.y / float(height_));
    pan_ = ImVec2((size.x - width_ * zoom_) * 0.5f, (size.y - height_ * zoom_) * 0.5f);
    fit_ = false;
  }
  ImGui::InvisibleButton("image", size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                                            ImGuiButtonFlags_MouseButtonMiddle);
  ImageView view;
  view.hovered = ImGui::IsItemHovered() || ImGui::IsItemActive();
  view.active = ImGui::IsItemActive();
  ImGuiIO& io = ImGui::GetIO();
  if (navigate && ImGui::IsItemHovered() && io.MouseWheel != 0) {
    const ImVec2 m = io.MousePos;
    const float ix = (m.x - origin.x - pan_.x) / zoom_, iy = (m.y - origin.y - pan_.y) / zoom_;
    zoom_ = std::clamp(zoom_ * std::pow(1.2f, io.MouseWheel), 0.02f, 64.0f);
    pan_ = ImVec2(m.x - origin.x - ix * zoom_, m.y - origin.y - iy * zoom_);
  }
  if (navigate && ImGui::IsItemActive() &&
      (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle)))
    pan_ = ImVec2(pan_.x + io.MouseDelta.x, pan_.y + io.MouseDelta.y);
  view.origin = ImVec2(origin.x + pan_.x, origin.y + pan_.y);
  view.scale = zoom_;
  view.width = width_;
  view.height = height_;
  return view;
}

// Pixel inspector: the values as stored, in the image's encoding.
void ImageViewer::inspect(const Image& image, const ImageView& view, bool navigate) const {
  const int c = image.channels();
  const ImVec2 p = view.to_image(ImGui::GetIO().MousePos);
  const int x = int(std::floor(p.x)), y = int(std::floor(p.y));
  if (view.hovered && x >= 0 && y >= 0 && x < width_ && y < height_) {
    const float* px = image.pixels.ptr<float>(y) + std::size_t(x) * c;
    char text[160];
    int n = std::snprintf(text, sizeof text, "(%d, %d):", x, y);
    for (int k = 0; k < c && n < int(sizeof text) - 16; ++k) n += std::snprintf(text + n, sizeof text - n, " %.4g", px[k]);
    ImGui::TextUnformatted(text);
  } else {
    ImGui::TextDisabled(navigate ? "hover for pixel values; wheel zooms, right-drag pans"
                                 : "hover for pixel values; drag orbits, right-drag pans, wheel dollies the camera");
  }
}

ImageView ImageViewer::draw(const Image& image, const void* identity, bool navigate) {
  if (image.empty()) {
    ImGui::TextDisabled("empty image");
    return {};
  }
  toolbar(image);
  const bool same_channels = std::equal(channels_, channels_ + 4, uploaded_channels_);
  if (identity != uploaded_ || exposure_ != uploaded_exposure_ || !same_channels || view_ != uploaded_view_) {
    upload(image);
    ++uploads_;
    uploaded_ = identity;
    uploaded_exposure_ = exposure_;
    uploaded_view_ = view_;
    std::copy(channels_, channels_ + 4, uploaded_channels_);
  }
  if (image.width() != width_ || image.height() != height_) {
    width_ = image.width();
    height_ = image.height();
    fit_ = true;
  }
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.y -= ImGui::GetTextLineHeightWithSpacing();
  size.x = std::max(size.x, 32.0f);
  size.y = std::max(size.y, 32.0f);
  const ImageView view = place(origin, size, navigate);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->PushClipRect(origin, ImVec2(origin.x + size.x, origin.y + size.y), true);
  draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture_)), view.to_screen(0, 0),
                 view.to_screen(width_, height_));
  draw->PopClipRect();
  inspect(image, view, navigate);
  return view;
}

}  // namespace loom::editor
