// Loom values <-> Python objects, the one place that knows both sides.
//
//   Image      <-> loom.Image: a read-only H×W×C float32 NumPy view of the
//                  engine's pixels (no copy), kept alive by the array; from
//                  Python any float32 array H×W or H×W×C (C 1-4) is copied in
//   Mesh, PointSet, Polylines <-> loom.Mesh / loom.PointSet / loom.Polylines
//                  holding NumPy views (vertices, faces, uv, normals, colors)
//   Json and the literal types (Float, Vec3, lists) <-> dict, list, numbers
//   anything else (Scene, Material) <-> loom.Value, an opaque handle
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "loom/value.hpp"

namespace loom::python {

namespace py = pybind11;

py::object to_python(const Value& value);
// Throws loom::Error saying what was expected and what was given.
Value from_python(const py::handle& object, const TypeInfo& type);

// For literal inputs: the JSON a graph file would hold (numbers, strings,
// lists, NumPy arrays and scalars). Throws loom::Error on NaN or infinities
// and on objects JSON cannot hold.
json to_json(const py::handle& object);
py::object from_json(const json& j);

// Whether the object is an in-memory value (an array, a mesh) rather than a
// literal: such inputs go into the graph as a held value (see graph.cpp).
bool is_held_value(const py::handle& object, const TypeInfo& type);

// Registers every value type a declaration may name (types register on first
// use, and a Python node may name one before any plugin used it).
void register_value_types();

void bind_values(py::module_& m);

}  // namespace loom::python
