#include "fonts.hpp"

#include <array>
#include <cstdio>
#include <system_error>

namespace loom::editor {

namespace {

// Canvas sizes: a zoomed node's text picks the nearest of these.
constexpr std::array<float, 6> kCanvasSizes = {11, 13, kUiFontSize, 20, 25, 32};
std::array<ImFont*, kCanvasSizes.size()> canvas_fonts{};

const ImWchar* glyph_ranges() {
  static const ImWchar ranges[] = {
      0x0020, 0x00FF,  // Basic Latin, Latin-1 (× ² ° ·)
      0x0370, 0x03FF,  // Greek (λ θ Σ μ)
      0x2010, 0x205E,  // punctuation (– — … ′)
      0x2070, 0x209F,  // super- and subscripts
      0x2190, 0x21FF,  // arrows (→ ←)
      0x2200, 0x22FF,  // mathematical operators (− ≤ ≈ ∇ ∑)
      0,
  };
  return ranges;
}

}  // namespace

bool load_fonts(const std::filesystem::path& file) {
  ImGuiIO& io = ImGui::GetIO();
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) {
    std::fprintf(stderr, "loom-editor: warning: %s not found (Debian package fonts-dejavu-core): using ImGui's "
                 "built-in font, without Greek and mathematical glyphs\n", file.c_str());
    canvas_fonts.fill(io.Fonts->AddFontDefault());
    return false;
  }
  ImFontConfig config;
  config.OversampleH = 2;
  io.Fonts->AddFontFromFileTTF(file.c_str(), kUiFontSize, &config, glyph_ranges());  // the default: first
  for (std::size_t i = 0; i < kCanvasSizes.size(); ++i)
    canvas_fonts[i] = kCanvasSizes[i] == kUiFontSize
                          ? io.Fonts->Fonts[0]
                          : io.Fonts->AddFontFromFileTTF(file.c_str(), kCanvasSizes[i], &config, glyph_ranges());
  return true;
}

ImFont* font_for(float pixels) {
  for (std::size_t i = 0; i < kCanvasSizes.size(); ++i)
    if (pixels <= kCanvasSizes[i] * 1.1f) return canvas_fonts[i] ? canvas_fonts[i] : ImGui::GetFont();
  return canvas_fonts.back() ? canvas_fonts.back() : ImGui::GetFont();
}

}  // namespace loom::editor
