// The ASAP and ARAP nodes through the engine, on generated meshes.
#include <mutex>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"

namespace {

loom::json graph(const loom::json& arap_inputs) {
  loom::json arap = {{"type", "ARAP"}, {"inputs", arap_inputs}};
  arap["inputs"]["mesh"] = {{"from", "hemi.mesh"}};
  return {{"loom", 1},
          {"nodes",
           {{"hemi", {{"type", "HemisphereMesh"}, {"inputs", {{"rings", 10}, {"segments", 40}}}}},
            {"asap", {{"type", "ASAP"}, {"inputs", {{"mesh", {{"from", "hemi.mesh"}}}}}}},
            {"arap", arap}}}};
}

TEST(ArapNodes, ArapFromTutteLowersTheEnergyWithoutFlips) {
  loom::testing::Engine engine;
  const auto doc = graph({{"init", "tutte"}, {"iterations", 50}});
  const auto energy = engine.output<std::vector<double>>(doc, "arap.energy");
  ASSERT_GE(energy.size(), 2u);
  for (size_t k = 1; k < energy.size(); ++k) EXPECT_LE(energy[k], energy[k - 1] * (1 + 1e-12));
  EXPECT_LT(energy.back(), energy.front());
  const auto report = engine.output<loom::json>(doc, "arap.distortion");
  EXPECT_EQ(report["flipped"], 0);
  EXPECT_LT(report["area_mean"].get<double>(), 1.5);
  const auto& mesh = engine.output<loom::Mesh>(doc, "arap.mesh");
  ASSERT_TRUE(mesh.has_uv());
  EXPECT_GE(mesh.UV.minCoeff(), 0);
  EXPECT_LE(mesh.UV.maxCoeff(), 1 + 1e-12);
  EXPECT_NEAR(mesh.UV.maxCoeff(), 1, 1e-12);
}

TEST(ArapNodes, AsapThenArapFromGivenUVs) {
  loom::testing::Engine engine;
  auto doc = graph({{"init", "given"}, {"iterations", 20}});
  doc["nodes"]["arap"]["inputs"]["mesh"] = {{"from", "asap.mesh"}};
  const auto asap_report = engine.output<loom::json>(doc, "asap.distortion");
  const auto arap_report = engine.output<loom::json>(doc, "arap.distortion");
  EXPECT_EQ(asap_report["flipped"], 0);
  EXPECT_LT(asap_report["angle_mean"].get<double>(), 1.1);  // nearly conformal
  EXPECT_LT(arap_report["arap_energy"].get<double>(), asap_report["arap_energy"].get<double>());
  EXPECT_EQ(engine.output<std::vector<double>>(doc, "asap.energy").size(), 1u);
}

// Whoever watches gets the map so far while ARAP iterates (at most every
// 0.08 s; the editor's viewer shows it): each is the map an ARAP stopped at
// that iteration gives, bit for bit, and the final result is the same with
// and without a listener.
struct MeshPartials : loom::Observer {
  std::mutex mutex;
  std::vector<std::pair<int, loom::Mesh>> maps;  // (iteration, mesh)
  bool wants_partial(const std::string&) const override { return true; }
  void node_partial(const std::string& id, const std::string& output, const loom::Value& value,
                    const loom::PartialInfo& info) override {
    std::lock_guard lock(mutex);
    EXPECT_EQ(id + "." + output, "arap.mesh");
    EXPECT_EQ(info.unit, "iterations");
    maps.emplace_back(int(info.done), value.as<loom::Mesh>());
  }
};

TEST(ArapNodes, WatchedIterationsPublishTheMapSoFar) {
  loom::testing::Engine engine;
  // A noisy hemisphere: its iterations go on lowering the energy for long.
  auto doc = graph({{"init", "tutte"}, {"iterations", 400}, {"tolerance", 0}});
  doc["nodes"]["hemi"]["inputs"] = {{"rings", 60}, {"segments", 240}, {"noise", 0.1}};  // 166 iterations, 0.8 s
  loom::EvalOptions o;
  o.targets = {loom::parse_target("arap.mesh")};
  MeshPartials partials;
  o.observer = &partials;
  const loom::EvalResult watched = engine.session().evaluate(engine.load(doc), o);
  ASSERT_TRUE(watched.ok()) << watched.nodes.at("arap").error;
  ASSERT_GE(partials.maps.size(), 2u) << "166 iterations of 14,400 vertices last over 0.16 s";
  const auto& maps = partials.maps;
  for (const auto* partial : {&maps.front(), &maps[maps.size() / 2], &maps.back()}) {
    const auto& [k, mesh] = *partial;
    auto stopped = doc;
    stopped["nodes"]["arap"]["inputs"]["iterations"] = k;
    const auto& reference = engine.output<loom::Mesh>(stopped, "arap.mesh");
    ASSERT_EQ(mesh.UV.rows(), reference.UV.rows());
    EXPECT_TRUE(mesh.UV == reference.UV) << "iteration " << k;
  }
  const auto& unwatched = engine.output<loom::Mesh>(doc, "arap.mesh");
  EXPECT_TRUE(watched.outputs.at("arap.mesh").at(0).as<loom::Mesh>().UV == unwatched.UV);
}

TEST(ArapNodes, ActionableErrors) {
  loom::testing::Engine engine;
  auto doc = graph({{"init", "given"}});
  EXPECT_THROW(engine.value(doc, "arap.mesh"), loom::Error);  // HemisphereMesh gives no UVs
  doc = graph({{"pin", 100000}});
  EXPECT_THROW(engine.value(doc, "arap.mesh"), loom::Error);
  doc = graph({{"model", "hybrid"}, {"lambda", 0.0}});
  EXPECT_THROW(engine.value(doc, "arap.mesh"), loom::Error);
}

}  // namespace
