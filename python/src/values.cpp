#include "values.hpp"

#include <cmath>
#include <cstring>

#include <pybind11/numpy.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "loom/builtin_types.hpp"
#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/point_pairs.hpp"
#include "loom/point_set.hpp"
#include "loom/polylines.hpp"
#include "loom/scene.hpp"

namespace loom::python {

namespace {

py::module_ values_module() { return py::module_::import("loom._values"); }

// A NumPy view of `count` rows of `cols` elements of T inside a value, which
// the array keeps alive (the capsule holds a copy of the Value).
template <class T>
py::object view(const Value& owner, const T* data, py::ssize_t rows, py::ssize_t cols,
               py::ssize_t row_stride, py::ssize_t col_stride) {
  if (rows == 0) return py::none();
  py::capsule base(new Value(owner), [](void* p) { delete static_cast<Value*>(p); });
  py::array a(py::dtype::of<T>(), {rows, cols}, {row_stride, col_stride}, data, base);
  a.attr("flags").attr("writeable") = false;
  return a;
}

// Eigen matrices are column-major: element (i, j) is at data + i + j * rows.
template <class M>
py::object eigen_view(const Value& owner, const M& m) {
  using T = typename M::Scalar;
  return view<T>(owner, m.data(), m.rows(), m.cols(), sizeof(T), sizeof(T) * m.rows());
}

py::object image_to_python(const Value& v) {
  const Image& image = v.as<Image>();
  const cv::Mat& p = image.pixels;
  const py::ssize_t c = p.channels();
  py::capsule base(new Value(v), [](void* q) { delete static_cast<Value*>(q); });
  py::array a(py::dtype::of<float>(), {py::ssize_t(p.rows), py::ssize_t(p.cols), c},
              {py::ssize_t(p.step[0]), py::ssize_t(sizeof(float) * c), py::ssize_t(sizeof(float))},
              p.ptr<float>(), base);
  a.attr("flags").attr("writeable") = false;
  return values_module().attr("Image")(a, image.encoding == Encoding::srgb ? "srgb" : "linear", image.space);
}

std::string type_name_of(const py::handle& o) { return py::str(py::type::of(o).attr("__name__")); }

// A C-contiguous float32 copy of `object` as an array, refusing what is not a
// real-valued array (the caller names what it is for).
py::array_t<float, py::array::c_style> float_array(const py::handle& object, const std::string& what) {
  if (!py::isinstance<py::array>(object))
    throw Error(what + ": expected a NumPy array of float32, got " + type_name_of(object));
  py::array a = py::reinterpret_borrow<py::array>(object);
  const char kind = a.dtype().kind();
  if (kind != 'f')
    throw Error(what + ": expected float32 values (float64 is converted), got dtype " +
                std::string(py::str(a.dtype())) + "; convert with .astype(numpy.float32)" +
                (kind == 'u' || kind == 'i' ? " (and scale 8-bit values by 1/255)" : ""));
  return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

Value image_from_python(const py::handle& object) {
  auto a = float_array(object, "image");
  if (a.ndim() != 2 && a.ndim() != 3)
    throw Error("image: expected an H×W or H×W×C array, got " + std::to_string(a.ndim()) + " dimensions");
  const py::ssize_t h = a.shape(0), w = a.shape(1), c = a.ndim() == 3 ? a.shape(2) : 1;
  if (c < 1 || c > 4) throw Error("image: expected 1 to 4 channels, got " + std::to_string(c));
  if (h == 0 || w == 0) throw Error("image: it is empty (" + std::to_string(h) + "×" + std::to_string(w) + ")");
  if (h > (1 << 20) || w > (1 << 20)) throw Error("image: larger than 1048576 pixels on a side");
  Image image(cv::Mat(int(h), int(w), CV_32FC(int(c))), Encoding::linear);
  if (py::hasattr(object, "encoding")) {
    const std::string e = py::str(object.attr("encoding"));
    if (e != "linear" && e != "srgb") throw Error("image: encoding must be \"linear\" or \"srgb\", got \"" + e + "\"");
    image.encoding = e == "srgb" ? Encoding::srgb : Encoding::linear;
  }
  if (py::hasattr(object, "space")) image.space = py::str(object.attr("space"));
  // One pass, in parallel bands of rows: each band copied, then checked while
  // it is in the cache.
  const std::size_t row_bytes = sizeof(float) * std::size_t(w * c);
  const auto* source = reinterpret_cast<const unsigned char*>(a.data());
  tbb::parallel_for(tbb::blocked_range<int>(0, int(h), 32), [&](const tbb::blocked_range<int>& rows) {
    std::memcpy(image.pixels.ptr(rows.begin()), source + row_bytes * std::size_t(rows.begin()),
                row_bytes * rows.size());
    require_finite(image.like(image.pixels.rowRange(rows.begin(), rows.end())), "image");
  });
  return Value::make(std::move(image));
}

// Rows×cols matrix from an attribute of `object` (None: empty unless required).
template <class M>
M matrix_attr(const py::handle& object, const char* name, int cols, bool required) {
  const std::string what = std::string(type_name_of(object)) + "." + name;
  py::object attr = py::getattr(object, name, py::none());
  if (attr.is_none()) {
    if (required) throw Error(what + " is missing");
    return M();
  }
  using T = typename M::Scalar;
  py::array a = py::array::ensure(attr);
  if (!a) throw Error(what + ": expected an array, got " + type_name_of(attr));
  const char kind = a.dtype().kind();
  if (std::is_integral_v<T> ? (kind != 'i' && kind != 'u') : (kind != 'f' && kind != 'i' && kind != 'u'))
    throw Error(what + ": expected " + (std::is_integral_v<T> ? "integers" : "numbers") + ", got dtype " +
                std::string(py::str(a.dtype())));
  if (a.ndim() != (cols == 1 ? 1 : 2) || (cols > 1 && a.shape(1) != cols))
    throw Error(what + ": expected shape (n, " + std::to_string(cols) + "), got " +
                std::string(py::str(attr.attr("shape"))));
  auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  M m(c.shape(0), cols);
  const T* p = c.data();
  for (py::ssize_t i = 0; i < c.shape(0); ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = p[i * cols + j];
  return m;
}

Value mesh_from_python(const py::handle& o) {
  if (!py::hasattr(o, "vertices") || !py::hasattr(o, "faces"))
    throw Error("expected a loom.Mesh (vertices, faces), got " + type_name_of(o));
  Mesh mesh;
  mesh.V = matrix_attr<Eigen::MatrixX3d>(o, "vertices", 3, true);
  mesh.F = matrix_attr<Eigen::MatrixX3i>(o, "faces", 3, true);
  mesh.UV = matrix_attr<Eigen::MatrixX2d>(o, "uv", 2, false);
  mesh.N = matrix_attr<Eigen::MatrixX3d>(o, "normals", 3, false);
  mesh.C = matrix_attr<Eigen::MatrixX3d>(o, "colors", 3, false);
  require_valid(mesh, "mesh");
  return Value::make(std::move(mesh));
}

Value points_from_python(const py::handle& o) {
  if (!py::hasattr(o, "points") || py::hasattr(o, "edges"))
    throw Error("expected a loom.PointSet (points, radius, colors), got " + type_name_of(o));
  PointSet s;
  s.P = matrix_attr<Eigen::MatrixX3d>(o, "points", 3, true);
  s.radius = matrix_attr<Eigen::MatrixXd>(o, "radius", 1, false);
  s.C = matrix_attr<Eigen::MatrixX3d>(o, "colors", 3, false);
  require_valid(s, "point set");
  return Value::make(std::move(s));
}

Value lines_from_python(const py::handle& o) {
  if (!py::hasattr(o, "points") || !py::hasattr(o, "edges"))
    throw Error("expected a loom.Polylines (points, edges, colors), got " + type_name_of(o));
  Polylines l;
  l.P = matrix_attr<Eigen::MatrixX3d>(o, "points", 3, true);
  l.E = matrix_attr<Eigen::MatrixX2i>(o, "edges", 2, true);
  l.C = matrix_attr<Eigen::MatrixX3d>(o, "colors", 3, false);
  require_valid(l, "polylines");
  return Value::make(std::move(l));
}

}  // namespace

py::object from_json(const json& j) {
  switch (j.type()) {
    case json::value_t::null: return py::none();
    case json::value_t::boolean: return py::bool_(j.get<bool>());
    case json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case json::value_t::number_float: return py::float_(j.get<double>());
    case json::value_t::string: return py::str(j.get<std::string>());
    case json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(from_json(e));
      return std::move(l);
    }
    case json::value_t::object: {
      py::dict d;
      for (const auto& [k, e] : j.items()) d[py::str(k)] = from_json(e);
      return std::move(d);
    }
    default: return py::none();
  }
}

json to_json(const py::handle& o) {
  if (o.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(o)) return o.cast<bool>();
  if (py::isinstance<py::array>(o)) return to_json(o.attr("tolist")());
  // NumPy scalars (numpy.float32(1), numpy.int64(2)) have item().
  if (!py::isinstance<py::int_>(o) && !py::isinstance<py::float_>(o) && py::hasattr(o, "item") &&
      py::hasattr(o, "dtype"))
    return to_json(o.attr("item")());
  if (py::isinstance<py::int_>(o)) return o.cast<std::int64_t>();
  if (py::isinstance<py::float_>(o)) {
    const double d = o.cast<double>();
    if (!std::isfinite(d)) throw Error("expected a finite number, got " + std::string(py::repr(o)));
    return d;
  }
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o)) {
    json a = json::array();
    for (const auto& e : o) a.push_back(to_json(e));
    return a;
  }
  if (py::isinstance<py::dict>(o)) {
    json d = json::object();
    for (const auto& [k, e] : o.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) throw Error("JSON object keys must be strings, got " + type_name_of(k));
      d[k.cast<std::string>()] = to_json(e);
    }
    return d;
  }
  throw Error("cannot write a " + type_name_of(o) + " as a graph value (expected a number, string, list or dict)");
}

py::object to_python(const Value& v) {
  if (!v) return py::none();
  const TypeInfo& t = *v.type();
  if (v.is<Image>()) return image_to_python(v);
  const py::module_ m = values_module();
  if (v.is<Mesh>()) {
    const Mesh& x = v.as<Mesh>();
    return m.attr("Mesh")(eigen_view(v, x.V), eigen_view(v, x.F), eigen_view(v, x.UV), eigen_view(v, x.N),
                          eigen_view(v, x.C));
  }
  if (v.is<PointSet>()) {
    const PointSet& x = v.as<PointSet>();
    py::object radius = x.radius.size() ? view<double>(v, x.radius.data(), x.radius.size(), 1, 8, 8)
                                                  .attr("reshape")(x.radius.size())
                                        : py::object(py::none());
    return m.attr("PointSet")(eigen_view(v, x.P), radius, eigen_view(v, x.C));
  }
  if (v.is<Polylines>()) {
    const Polylines& x = v.as<Polylines>();
    return m.attr("Polylines")(eigen_view(v, x.P), eigen_view(v, x.E), eigen_view(v, x.C));
  }
  if (t.to_json) return from_json(t.to_json(v.data()));
  return py::cast(v);
}

bool is_held_value(const py::handle& o, const TypeInfo& type) {
  if (py::isinstance<Value>(o)) return true;
  if (type.literal() && !is_any(type)) return false;
  return py::isinstance<py::array>(o) || py::hasattr(o, "vertices") || py::hasattr(o, "points");
}

Value from_python(const py::handle& o, const TypeInfo& type) {
  if (py::isinstance<Value>(o)) {
    const Value& v = o.cast<const Value&>();
    if (!is_any(type) && v.type()->storage != type.storage)
      throw Error("expected " + type.name + ", got a loom.Value holding " + v.type()->name);
    return v;
  }
  const std::string& s = type.storage;
  if (s == "Image") return image_from_python(o);
  if (s == "Mesh") return mesh_from_python(o);
  if (s == "PointSet") return points_from_python(o);
  if (s == "Polylines") return lines_from_python(o);
  if (is_any(type)) {
    if (py::isinstance<py::array>(o) && py::reinterpret_borrow<py::array>(o).dtype().kind() == 'f' &&
        (py::reinterpret_borrow<py::array>(o).ndim() == 2 || py::reinterpret_borrow<py::array>(o).ndim() == 3))
      return image_from_python(o);  // a float array of 2 or 3 dimensions: an image
    if (py::hasattr(o, "vertices")) return mesh_from_python(o);
    if (py::hasattr(o, "edges")) return lines_from_python(o);
    if (py::hasattr(o, "points")) return points_from_python(o);
    return Value(&type_of<json>(), type_of<json>().from_json(to_json(o)));
  }
  if (!type.literal())
    throw Error("expected " + type.name + " (pass the loom.Value a node returned), got " + type_name_of(o));
  return Value(&type, type.from_json(to_json(o)));
}

void register_value_types() {
  type_of<bool>(), type_of<int>(), type_of<double>(), type_of<std::string>();
  type_of<Vec2i>(), type_of<Vec2>(), type_of<Vec3i>(), type_of<Vec3>(), type_of<Color>();
  type_of<std::vector<int>>(), type_of<std::vector<double>>(), type_of<std::vector<std::string>>();
  type_of<std::vector<Vec2>>(), type_of<std::vector<Vec3>>(), type_of<json>(), type_of<Any>(), enum_type();
  type_of<PointPairs>(), type_of<Image>(), type_of<Mesh>(), type_of<PointSet>(), type_of<Polylines>();
  type_of<Scene>(), type_of<Material>();
}

void bind_values(py::module_& m) {
  py::class_<Value>(m, "Value", "An engine value with no Python form (a Scene, a Material): pass it "
                                "back as a node input.")
      .def_property_readonly("type", [](const Value& v) { return v.type()->name; })
      .def("__repr__", [](const Value& v) {
        return "<loom.Value " + (v.type()->summary ? v.type()->summary(v.data()) : v.type()->name) + ">";
      });
}

}  // namespace loom::python
