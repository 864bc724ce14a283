// The editor's typeface: DejaVu Sans from Debian's fonts-dejavu-core, with
// the glyphs node descriptions use (Greek λ θ Σ, − × ² ≤ → and the like),
// baked at the UI's size and at a ladder of sizes for the zoomed canvas, so
// canvas text is drawn from the nearest baked size instead of a stretched
// bitmap. Without the font file ImGui's built-in font is used and a warning
// names the package.
#pragma once

#include <filesystem>

#include <imgui.h>

namespace loom::editor {

// The UI's text size in pixels.
constexpr float kUiFontSize = 16;

// Loads the fonts into the current ImGui context (before the first frame).
// Returns false (and warns on stderr) when the font file is missing.
bool load_fonts(const std::filesystem::path& file = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf");
// The baked font to draw text of `pixels` height with (draw it at `pixels`).
ImFont* font_for(float pixels);

}  // namespace loom::editor
