// Canvas units and small vector helpers shared by the canvas's drawing and
// its mouse and keyboard handling.
#pragma once

#include <cmath>

#include <imgui.h>

namespace loom::editor::canvas_geometry {

// Node box layout in canvas units (scaled by the zoom on screen).
constexpr float kWidth = 200, kHeader = 26, kRow = 20, kFooter = 18, kSocket = 5.5f;

inline ImVec2 operator+(ImVec2 a, ImVec2 b) { return {a.x + b.x, a.y + b.y}; }
inline ImVec2 operator-(ImVec2 a, ImVec2 b) { return {a.x - b.x, a.y - b.y}; }
inline ImVec2 operator*(ImVec2 a, float s) { return {a.x * s, a.y * s}; }
inline float distance(ImVec2 a, ImVec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace loom::editor::canvas_geometry
