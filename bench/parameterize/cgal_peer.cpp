#include "cgal_peer.hpp"

#include <stdexcept>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Barycentric_mapping_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Error_code.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <Eigen/SparseLU>

namespace loom::bench {

namespace SMP = CGAL::Surface_mesh_parameterization;
using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexDescriptor = boost::graph_traits<Mesh>::vertex_descriptor;
using HalfedgeDescriptor = boost::graph_traits<Mesh>::halfedge_descriptor;

struct CgalPeer {
  Mesh mesh;
};

namespace {

// A border parameterizer that places the border where we say, so CGAL and
// Loom solve for the same interior.
struct GivenBorder {
  const Eigen::MatrixX2d* uv = nullptr;
  template <class UVMap, class IndexMap, class ParameterizedMap>
  SMP::Error_code parameterize(const Mesh& mesh, HalfedgeDescriptor bhd, UVMap uvmap, IndexMap,
                               ParameterizedMap vpmap) const {
    for (HalfedgeDescriptor h : CGAL::halfedges_around_face(bhd, mesh)) {
      const VertexDescriptor v = CGAL::source(h, mesh);
      put(uvmap, v, Kernel::Point_2((*uv)(v.idx(), 0), (*uv)(v.idx(), 1)));
      put(vpmap, v, true);
    }
    return SMP::OK;
  }
  bool is_border_convex() const { return true; }
};

using Bicgstab = CGAL::Eigen_solver_traits<
    Eigen::BiCGSTAB<CGAL::Eigen_sparse_matrix<double>::EigenType, Eigen::IncompleteLUT<double>>>;
using SparseLu = CGAL::Eigen_solver_traits<
    Eigen::SparseLU<CGAL::Eigen_sparse_matrix<double>::EigenType, Eigen::COLAMDOrdering<int>>>;

template <class Parameterizer>
Eigen::MatrixX2d run(Mesh& mesh, const Eigen::MatrixX2d& border_uv, int border_vertex) {
  HalfedgeDescriptor bhd;
  for (HalfedgeDescriptor h : CGAL::halfedges_around_target(VertexDescriptor(border_vertex), mesh))
    if (CGAL::is_border(h, mesh)) bhd = h;
  if (bhd == HalfedgeDescriptor()) throw std::runtime_error("border vertex is not on the border");
  auto uvmap = mesh.add_property_map<VertexDescriptor, Kernel::Point_2>("v:uv").first;
  Parameterizer p(GivenBorder{&border_uv});
  const SMP::Error_code err = SMP::parameterize(mesh, p, bhd, uvmap);
  if (err != SMP::OK) throw std::runtime_error(std::string("CGAL: ") + SMP::get_error_message(err));
  Eigen::MatrixX2d UV(mesh.number_of_vertices(), 2);
  for (VertexDescriptor v : mesh.vertices()) UV.row(v.idx()) << uvmap[v].x(), uvmap[v].y();
  mesh.remove_property_map(uvmap);
  return UV;
}

template <class Solver>
Eigen::MatrixX2d dispatch(Mesh& mesh, const Eigen::MatrixX2d& uv, int v, const std::string& method) {
  if (method == "uniform") return run<SMP::Barycentric_mapping_parameterizer_3<Mesh, GivenBorder, Solver>>(mesh, uv, v);
  if (method == "cotangent") return run<SMP::Discrete_conformal_map_parameterizer_3<Mesh, GivenBorder, Solver>>(mesh, uv, v);
  if (method == "mean_value") return run<SMP::Mean_value_coordinates_parameterizer_3<Mesh, GivenBorder, Solver>>(mesh, uv, v);
  throw std::runtime_error("CGAL has no peer for " + method);
}

}  // namespace

CgalPeer* cgal_build(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  auto* peer = new CgalPeer;
  for (int v = 0; v < V.rows(); ++v) peer->mesh.add_vertex(Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)));
  for (int f = 0; f < F.rows(); ++f)
    if (peer->mesh.add_face(VertexDescriptor(F(f, 0)), VertexDescriptor(F(f, 1)), VertexDescriptor(F(f, 2))) ==
        Mesh::null_face())
      throw std::runtime_error("CGAL refused face " + std::to_string(f));
  return peer;
}

void cgal_free(CgalPeer* peer) { delete peer; }

Eigen::MatrixX2d cgal_parameterize(CgalPeer& peer, const Eigen::MatrixX2d& border_uv, int border_vertex,
                                   const std::string& method, const std::string& solver) {
  if (solver == "sparselu") return dispatch<SparseLu>(peer.mesh, border_uv, border_vertex, method);
  return dispatch<Bicgstab>(peer.mesh, border_uv, border_vertex, method);
}

}  // namespace loom::bench
