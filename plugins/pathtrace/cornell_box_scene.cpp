#include "cornell_box_scene.hpp"

#include "sphere_mesh.hpp"

#include <cmath>
#include <array>
#include <vector>

namespace loom::pathtrace {

namespace {

using V3 = Eigen::Vector3d;

// Quads as two triangles each, every normal turned towards (inward = true) or
// away from `reference`.
std::shared_ptr<Mesh> quads(const std::vector<std::array<V3, 4>>& faces, const V3& reference,
                            bool toward) {
  auto mesh = std::make_shared<Mesh>();
  mesh->V.resize(4 * Eigen::Index(faces.size()), 3);
  mesh->F.resize(2 * Eigen::Index(faces.size()), 3);
  for (std::size_t q = 0; q < faces.size(); ++q) {
    std::array<V3, 4> f = faces[q];
    const V3 n = (f[1] - f[0]).cross(f[2] - f[0]);
    const V3 center = (f[0] + f[1] + f[2] + f[3]) / 4;
    if ((n.dot(reference - center) > 0) != toward) std::swap(f[1], f[3]);
    const int b = 4 * int(q);
    for (int k = 0; k < 4; ++k) mesh->V.row(b + k) = f[k].transpose();
    mesh->F.row(2 * q) << b, b + 1, b + 2;
    mesh->F.row(2 * q + 1) << b, b + 2, b + 3;
  }
  return mesh;
}

SceneObject object(std::string name, std::shared_ptr<Mesh> mesh, const V3& color) {
  SceneObject o;
  o.name = std::move(name);
  o.mesh = std::move(mesh);
  o.material.base_color = color;
  return o;
}

}  // namespace

Scene cornell_box(const CornellBoxOptions& opt) {
  Scene scene;
  const V3 inside(278, 274.4, 279.6);
  scene.objects.push_back(object(
      "floor", quads({{V3(552.8, 0, 0), V3(0, 0, 0), V3(0, 0, 559.2), V3(549.6, 0, 559.2)}}, inside, true),
      opt.white));
  scene.objects.push_back(object(
      "ceiling",
      quads({{V3(556, 548.8, 0), V3(556, 548.8, 559.2), V3(0, 548.8, 559.2), V3(0, 548.8, 0)}}, inside, true),
      opt.white));
  scene.objects.push_back(object(
      "back wall",
      quads({{V3(549.6, 0, 559.2), V3(0, 0, 559.2), V3(0, 548.8, 559.2), V3(556, 548.8, 559.2)}}, inside, true),
      opt.white));
  scene.objects.push_back(object(
      "green wall",
      quads({{V3(0, 0, 559.2), V3(0, 0, 0), V3(0, 548.8, 0), V3(0, 548.8, 559.2)}}, inside, true), opt.green));
  scene.objects.push_back(object(
      "red wall",
      quads({{V3(552.8, 0, 0), V3(549.6, 0, 559.2), V3(556, 548.8, 559.2), V3(556, 548.8, 0)}}, inside, true),
      opt.red));
  SceneObject light = object(
      "light",
      quads({{V3(343, 548.7, 227), V3(343, 548.7, 332), V3(213, 548.7, 332), V3(213, 548.7, 227)}},
            V3(278, 0, 279.5), true),
      V3(0.78, 0.78, 0.78));
  light.material.emission = opt.light_radiance;
  scene.objects.push_back(light);
  if (opt.contents == CornellContents::blocks) {
    scene.objects.push_back(object(
        "short block",
        quads({{V3(130, 165, 65), V3(82, 165, 225), V3(240, 165, 272), V3(290, 165, 114)},
               {V3(290, 0, 114), V3(290, 165, 114), V3(240, 165, 272), V3(240, 0, 272)},
               {V3(130, 0, 65), V3(130, 165, 65), V3(290, 165, 114), V3(290, 0, 114)},
               {V3(82, 0, 225), V3(82, 165, 225), V3(130, 165, 65), V3(130, 0, 65)},
               {V3(240, 0, 272), V3(240, 165, 272), V3(82, 165, 225), V3(82, 0, 225)}},
              V3(186, 82.5, 169), false),
        opt.white));
    scene.objects.push_back(object(
        "tall block",
        quads({{V3(423, 330, 247), V3(265, 330, 296), V3(314, 330, 456), V3(472, 330, 406)},
               {V3(423, 0, 247), V3(423, 330, 247), V3(472, 330, 406), V3(472, 0, 406)},
               {V3(472, 0, 406), V3(472, 330, 406), V3(314, 330, 456), V3(314, 0, 456)},
               {V3(314, 0, 456), V3(314, 330, 456), V3(265, 330, 296), V3(265, 0, 296)},
               {V3(265, 0, 296), V3(265, 330, 296), V3(423, 330, 247), V3(423, 0, 247)}},
              V3(368.5, 165, 351.25), false),
        opt.white));
  } else if (opt.contents == CornellContents::spheres) {
    SceneObject mirror = object("mirror ball", sphere_mesh(V3(390, 100, 370), 100, 48, 96), V3(0.95, 0.95, 0.95));
    mirror.material.model = Material::Model::conductor;
    mirror.material.roughness = 0;
    SceneObject glass = object("glass ball", sphere_mesh(V3(170, 100, 200), 100, 48, 96), V3(1, 1, 1));
    glass.material.model = Material::Model::dielectric;
    glass.material.roughness = 0;
    glass.material.ior = 1.5;
    scene.objects.push_back(mirror);
    scene.objects.push_back(glass);
  }
  Camera camera;
  camera.eye = V3(278, 273, -800);
  camera.target = V3(278, 273, 0);
  camera.up = V3(0, 1, 0);
  camera.fov_y = 2 * std::atan(0.0125 / 0.035);  // 25 mm film at 35 mm focal length: 39.3°
  camera.near_plane = 1;
  camera.far_plane = 5000;
  scene.camera = camera;
  return scene;
}

}  // namespace loom::pathtrace
