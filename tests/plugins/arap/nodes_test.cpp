// The ASAP and ARAP nodes through the engine, on generated meshes.
#include <gtest/gtest.h>

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
