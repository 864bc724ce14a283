// The generate plugin's shapes as functions: the nodes call them, and so do
// the tests and benchmarks that need a grid, a disk, a hemisphere, a sphere or
// a checkerboard (link loom_generate_core; never the plugin itself).
//
// Mesh counts are validated here (a clear loom::Error naming the input), so a
// caller outside the engine gets the same errors as a node.
#pragma once

#include <functional>
#include <random>

#include <opencv2/core.hpp>

#include "loom/builtin_types.hpp"
#include "loom/mesh.hpp"

namespace loom::generate {

// A vertex position from the grid's two parameters.
using Position = std::function<Eigen::Vector3d(double, double)>;
// A node's cancellation check (may throw to stop), called every 64 rows of
// vertices, faces or pixels; empty: none.
using Check = std::function<void()>;

// A grid of nx by ny cells, (nx+1)(ny+1) vertices: vertex (i, j) is row
// j·(nx+1) + i, at position(u, v) with u = i/nx, v = j/ny, and has UV (u, v).
// Each cell is split along its (i, j)–(i+1, j+1) diagonal into the triangles
// (i,j) (i+1,j) (i+1,j+1) and (i,j) (i+1,j+1) (i,j+1): counter-clockwise in
// (u, v). Cells where keep(i, j) is false are left out (holes; their
// vertices stay); an empty keep keeps every cell.
Mesh grid_mesh(int nx, int ny, const Position& position, const std::function<bool(int, int)>& keep = {},
               const Check& check = {});

// A polar grid: a pole vertex, then `rings` rings of `segments` vertices
// each. position(t, phi) gives the vertex at radial parameter t in (0, 1]
// (ring k has t = k / rings) and angle phi = 2π s / segments; the pole is
// position(0, 0) and is called first, then ring by ring. Triangles are
// counter-clockwise seen from +z (outside). #F = segments·(2·rings − 1).
Mesh polar_mesh(int rings, int segments, const Position& position, const Check& check = {});

// Validates ring and segment counts with a message naming the input, and
// their product (at most 2^24 vertices).
void require_polar_counts(int rings, int segments);

// GridMesh: the rectangle [−w/2, w/2] × [−h/2, h/2] in z = 0 (size = (w, h)),
// nx by ny cells, UVs spanning [0, 1]².
Mesh rectangle_mesh(const Vec2& size, int nx, int ny, const Check& check = {});

// DiskMesh: a disk of radius R in the xy plane on a polar grid, lifted to
// z = h sin(2πx/R) sin(2πy/R) (1 − r²/R²) (flat boundary circle).
Mesh disk_mesh(double radius, int rings, int segments, double bump_height, const Check& check = {});

// HemisphereMesh: z >= 0 of the sphere of radius R on a polar grid (pole at
// +z, boundary on the equator); each vertex, the pole first, moved radially
// to R (1 + noise·u) with u uniform in [−1, 1) drawn from rng.
Mesh hemisphere_mesh(double radius, int rings, int segments, double noise, std::mt19937_64& rng,
                     const Check& check = {});

// UVSphere: a closed sphere, poles at ±z (first and last vertex) and
// rings − 1 latitude rings of `segments` vertices; N = outward unit normals.
Mesh uv_sphere_mesh(double radius, int rings, int segments, const Check& check = {});

// Checkerboard: width × height (size) RGB pixels, CV_32FC3, cells squares
// along the shorter side; the corner square has color a.
cv::Mat checkerboard(const Vec2i& size, int cells, const Color& a, const Color& b, const Check& check = {});

}  // namespace loom::generate
