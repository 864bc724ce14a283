// Normal mapping at a ray hit, in Render's convention (scene.hpp): the map's
// [0, 1] values encode a tangent-space vector m = 2 c - 1 (x along +u, y along
// +v, z along the normal); the world-space shading normal is
//   n' = normalize(m.x T + m.y B + m.z n)
// with T, B from dP/du, dP/dv by Gram-Schmidt against n
// (loom::numerics::tangent_basis, the same frame as Render's shader).
//
// A mapped normal can tilt away from the viewer so that wo falls below its
// horizon although it is above the geometric surface (black or leaking
// shading). Guard (a bend, in the spirit of Keller et al. 2017, "Towards
// Accurate and Practical Shading Normals"): n' is tilted towards the
// geometric normal ng, n'' = normalize(n' + k ng), with the smallest k >= 0
// that puts wo at least slightly above the horizon (wo·n'' > 0). Directions
// on the other side of the geometric surface than wo are then cut by the
// integrator (pbrt's rule). Not energy conserving in the way Schüssler et
// al. 2017's microfacet-based normal mapping is; see docs/pathtrace.md.
#pragma once

#include "sampling.hpp"

namespace loom::pathtrace {

// n unit shading normal, texel the map's value in [0, 1]³. Returns n when
// the UV tangents give no frame or the mapped vector is degenerate.
Vec3f mapped_normal(const Vec3f& n, const Vec3f& dpdu, const Vec3f& dpdv, const Vec3f& texel);

// ns unit shading normal, ng unit geometric normal on ns's side, wo unit
// towards the viewer (either side of the surface). Returns ns, bent towards
// ng when wo is below ns's horizon on the side of the surface wo is on.
Vec3f bend_above_horizon(const Vec3f& ns, const Vec3f& ng, const Vec3f& wo);

}  // namespace loom::pathtrace
