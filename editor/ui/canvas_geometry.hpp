// Canvas units and small vector helpers shared by the canvas's drawing and
// its mouse and keyboard handling.
#pragma once

#include <cmath>

#include <imgui.h>

#include "model/auto_layout.hpp"

namespace loom::editor::canvas_geometry {

// Node box layout in canvas units (scaled by the zoom on screen), as the
// automatic layout places boxes (model/auto_layout.hpp).
constexpr float kWidth = float(kNodeWidth), kHeader = float(kNodeHeader), kRow = float(kNodeRow),
                kFooter = float(kNodeFooter), kSocket = 5.5f;
// Below this zoom node text is left out (under ~8 px it is a grey smear).
constexpr float kLabelZoom = 0.5f;
// Frame-all never zooms out below this (16 px text at 0.75 is 12 px, as
// Blender's node labels): a graph larger than the view is scrolled instead.
constexpr float kMinFitZoom = 0.75f;

// Groups: the band under a group node's header, the interface's inputs and outputs inside.
constexpr ImU32 kGroupColor = IM_COL32(175, 130, 235, 255);

inline ImVec2 operator+(ImVec2 a, ImVec2 b) { return {a.x + b.x, a.y + b.y}; }
inline ImVec2 operator-(ImVec2 a, ImVec2 b) { return {a.x - b.x, a.y - b.y}; }
inline ImVec2 operator*(ImVec2 a, float s) { return {a.x * s, a.y * s}; }
inline float distance(ImVec2 a, ImVec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace loom::editor::canvas_geometry
