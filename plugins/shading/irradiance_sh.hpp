// Diffuse light from a lat-long environment map by 9 spherical-harmonic
// coefficients (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for
// Irradiance Environment Maps"): the irradiance E(n) of a convex Lambertian
// surface keeps only bands l <= 2 of the radiance, with an error of a few
// percent for natural lighting.
#pragma once

#include <array>

#include <Eigen/Core>

#include "loom/image.hpp"

namespace loom::shading {

// Radiance coefficients L_lm (R&H eq. 10), in the order (0,0) (1,-1) (1,0)
// (1,1) (2,-2) (2,-1) (2,0) (2,1) (2,2), RGB each.
using Sh9 = std::array<Eigen::Vector3d, 9>;

// The real SH basis Y_lm(d) for a unit direction (R&H eq. 3), same order.
std::array<double, 9> sh9_basis(const Eigen::Vector3d& d);

// Projects a lat-long radiance map (loom::latlong_direction's convention,
// turned by `rotation` about +y; 1 channel gray or RGB first) on the basis:
// L_lm = sum over texels of L Y_lm times the texel's exact solid angle.
Sh9 sh9_project(const Image& map, double rotation);

// Irradiance coefficients: L_lm times the clamped-cosine convolution A_l
// (A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4; R&H eq. 8), so that
// E(n) = sum E_lm Y_lm(n).
Sh9 sh9_irradiance_coefficients(const Sh9& radiance);
// E(n) from irradiance coefficients (R&H eq. 7).
Eigen::Vector3d sh9_irradiance(const Sh9& irradiance_coefficients, const Eigen::Vector3d& n);

}  // namespace loom::shading
