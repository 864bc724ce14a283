#include "scenes.hpp"

#include <fstream>
#include <map>
#include <sstream>

#include "loom/error.hpp"
#include "night_sky_map.hpp"
#include "sphere_mesh.hpp"

namespace loom::pathtrace::bench {

namespace {

// A camera at `eye` looking at `target`, y up, with a vertical field of view in degrees.
Camera look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double fov_y_degrees) {
  Camera camera;
  camera.eye = eye;
  camera.target = target;
  camera.fov_y = fov_y_degrees * M_PI / 180;
  return camera;
}

std::shared_ptr<Mesh> ground_quad(double half) {
  auto m = std::make_shared<Mesh>();
  m->V.resize(4, 3);
  m->V << -half, 0, -half, half, 0, -half, half, 0, half, -half, 0, half;
  m->F.resize(2, 3);
  m->F << 0, 2, 1, 0, 3, 2;  // facing +y
  return m;
}

SceneObject ball(const Eigen::Vector3d& c, double r, Material::Model model, const Eigen::Vector3d& color,
                 double roughness) {
  SceneObject o;
  o.mesh = sphere_mesh(c, r, 48, 96);
  o.material.model = model;
  o.material.base_color = color;
  o.material.roughness = roughness;
  return o;
}

// An axis-aligned box of the given corners, faces outwards.
std::shared_ptr<Mesh> box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  auto m = std::make_shared<Mesh>();
  m->V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m->V.row(i) << (i & 1 ? hi : lo).x(), (i & 2 ? hi : lo).y(), (i & 4 ? hi : lo).z();
  m->F.resize(12, 3);
  m->F << 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5;
  return m;
}

}  // namespace

Scene embree_cornell_box(const std::filesystem::path& models) {
  std::map<std::string, Eigen::Vector3d> kd;
  {
    std::ifstream mtl(models / "cornell_box.mtl");
    if (!mtl) throw Error("cannot read " + (models / "cornell_box.mtl").string());
    std::string line, current;
    while (std::getline(mtl, line)) {
      std::istringstream s(line);
      std::string key;
      s >> key;
      if (key == "newmtl") s >> current;
      if (key == "Kd") s >> kd[current].x() >> kd[current].y() >> kd[current].z();
    }
  }
  std::ifstream obj(models / "cornell_box.obj");
  if (!obj) throw Error("cannot read " + (models / "cornell_box.obj").string());
  std::vector<Eigen::Vector3d> V;
  std::map<std::string, std::vector<Eigen::Vector3i>> faces;  // by material
  std::string line, material = "white";
  while (std::getline(obj, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "v") {
      Eigen::Vector3d v;
      s >> v.x() >> v.y() >> v.z();
      V.push_back(v);
    } else if (key == "usemtl") {
      s >> material;
    } else if (key == "f") {
      std::vector<int> idx;
      std::string token;
      while (s >> token) {
        const int i = std::stoi(token.substr(0, token.find('/')));
        idx.push_back(i < 0 ? int(V.size()) + i : i - 1);
      }
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) faces[material].emplace_back(idx[0], idx[k], idx[k + 1]);
    }
  }
  Scene scene;
  for (const auto& [name, F] : faces) {
    auto mesh = std::make_shared<Mesh>();
    mesh->V.resize(Eigen::Index(V.size()), 3);
    for (std::size_t i = 0; i < V.size(); ++i) mesh->V.row(Eigen::Index(i)) = V[i].transpose();
    mesh->F.resize(Eigen::Index(F.size()), 3);
    for (std::size_t i = 0; i < F.size(); ++i) mesh->F.row(Eigen::Index(i)) = F[i].transpose();
    SceneObject o;
    o.name = name;
    o.mesh = mesh;
    o.material.base_color = kd.count(name) ? kd[name] : Eigen::Vector3d(1, 1, 1);
    scene.objects.push_back(o);
  }
  Light light;
  light.kind = Light::Kind::point;
  light.position = Eigen::Vector3d(213, 300, 227);
  light.intensity = 100000;
  scene.lights.push_back(light);
  scene.camera = look_at({278, 273, -800}, {278, 273, 0}, 37);
  return scene;
}

Scene embree_cornell_box_with_ball(const std::filesystem::path& models, int rings) {
  Scene scene = embree_cornell_box(models);
  SceneObject ball;
  ball.name = "ball";
  ball.mesh = sphere_mesh({370, 130, 200}, 130, rings, 2 * rings);
  ball.material.base_color = Eigen::Vector3d(0.8, 0.8, 0.8);
  scene.objects.push_back(ball);
  return scene;
}

Scene night_scene(bool lamp) {
  Scene scene;
  scene.objects.push_back(ball({0, 1, 0}, 1, Material::Model::plastic, {0.7, 0.15, 0.1}, 0.25));
  scene.objects.push_back(ball({-2.2, 0.7, 0.6}, 0.7, Material::Model::conductor, {0.95, 0.8, 0.5}, 0.15));
  SceneObject glass = ball({2.0, 0.6, 0.9}, 0.6, Material::Model::dielectric, {1, 1, 1}, 0);
  scene.objects.push_back(glass);
  SceneObject ground;
  ground.mesh = ground_quad(15);
  ground.material.base_color = Eigen::Vector3d(0.45, 0.45, 0.42);
  scene.objects.push_back(ground);
  NightSkyOptions sky;
  sky.moon_elevation = 35 * M_PI / 180;
  sky.moon_azimuth = 140 * M_PI / 180;
  sky.moon_radius = 1.5 * M_PI / 180;
  scene.environment.map = std::make_shared<Image>(night_sky_map(sky));
  if (lamp) {
    Light l;
    l.position = Eigen::Vector3d(0.8, 2.4, 2.2);
    l.color = Eigen::Vector3d(1.0, 0.75, 0.45);
    l.intensity = 12;
    scene.lights.push_back(l);
  }
  scene.camera = look_at({0, 1.8, 7}, {0, 0.8, 0}, 40);
  return scene;
}

Scene bright_pixel_scene() {
  Scene scene;
  scene.objects.push_back(ball({0, 1, 0}, 1, Material::Model::diffuse, {0.8, 0.8, 0.8}, 0.5));
  SceneObject ground;
  ground.mesh = ground_quad(6);
  ground.material.base_color = Eigen::Vector3d(0.5, 0.5, 0.5);
  scene.objects.push_back(ground);
  cv::Mat map(32, 64, CV_32FC3, cv::Scalar::all(0.05));
  map.at<cv::Vec3f>(8, 40) = cv::Vec3f(20000, 20000, 20000);  // a small sun, 45° up
  scene.environment.map = std::make_shared<Image>(map, Encoding::linear);
  scene.camera = look_at({0, 2, 5}, {0, 0.8, 0}, 45);
  return scene;
}

Scene emissive_mesh_scene() {
  Scene scene;
  auto flat = [](std::shared_ptr<Mesh> m) {
    m->N.resize(0, 3);
    return m;
  };
  SceneObject ground;
  ground.name = "ground";
  ground.mesh = ground_quad(8);
  ground.material.base_color = Eigen::Vector3d(0.5, 0.5, 0.5);
  scene.objects.push_back(ground);
  SceneObject sphere;
  sphere.name = "ball";
  sphere.mesh = flat(sphere_mesh({-1, 1, 0}, 1, 24, 48));
  sphere.material.base_color = Eigen::Vector3d(0.75, 0.3, 0.2);
  scene.objects.push_back(sphere);
  SceneObject box;
  box.name = "box";
  box.mesh = box_mesh({0.6, 0, -0.4}, {1.8, 1.2, 0.8});
  box.material.base_color = Eigen::Vector3d(0.3, 0.5, 0.7);
  scene.objects.push_back(box);
  SceneObject lamp;
  lamp.name = "glowing sphere";
  lamp.mesh = flat(sphere_mesh({0.6, 3.0, 1.6}, 0.5, 24, 48));
  lamp.material.base_color = Eigen::Vector3d(0.8, 0.8, 0.8);
  lamp.material.emission = Eigen::Vector3d(12, 10, 8);
  scene.objects.push_back(lamp);
  scene.environment.color = Eigen::Vector3d(0.05, 0.07, 0.1);
  scene.camera = look_at({0, 2.2, 7}, {0, 0.9, 0}, 40);
  return scene;
}

}  // namespace loom::pathtrace::bench
