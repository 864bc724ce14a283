// NBody's numbers out of Loom: the trajectory table written by SaveJSON, the
// outputs printed in full by `loom run --target … --json`, and the energy
// error of massless ships; each read back and compared with the node's values
// or an analytic reference.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "loom/polylines.hpp"
#include "loom/testing.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

// A ship on the circular orbit r = 1, v = 1 (GM = 1) about a fixed planet.
json circular_orbit(double ship_mass) {
  return {{"type", "NBody"},
          {"inputs", {{"masses", {1.0, ship_mass}}, {"duration", 6.0}, {"dt", 0.01}, {"samples", 61}}}};
}

TEST(NumbersOut, TrajectoryTableSavedAsJsonMatchesTheNode) {
  testing::Engine e;
  const json doc = {{"loom", 1},
                    {"nodes",
                     {{"orbit", circular_orbit(0)},
                      {"save", {{"type", "SaveJSON"}, {"inputs", {{"value", {{"from", "orbit.table"}}}, {"path", "orbit.json"}}}}}}}};
  Graph g = e.load(doc);
  const auto out = test::temp_dir();
  testing::Run r = e.run(g, {"save", "orbit.table", "orbit.trajectories"}, out);
  ASSERT_TRUE(r.ok());
  std::ifstream f(out / "orbit.json");
  const json file = json::parse(f);
  const json& table = r.output<json>("orbit.table");
  EXPECT_EQ(file, table);  // every number exactly (JSON round-trips doubles)
  const auto& lines = r.output<Polylines>("orbit.trajectories");
  ASSERT_EQ(file["time"].size(), 61u);
  for (int i = 0; i < 61; ++i) {
    EXPECT_NEAR(file["time"][i].get<double>(), 0.1 * i, 1e-12);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(file["bodies"][1]["position"][i][k].get<double>(), lines.P(61 + i, k)) << "sample " << i;
    // The circular orbit in closed form: x = (cos t, sin t), v = (−sin t, cos t).
    const double t = file["time"][i].get<double>();
    EXPECT_NEAR(file["bodies"][1]["position"][i][0].get<double>(), std::cos(t), 1e-7);
    EXPECT_NEAR(file["bodies"][1]["velocity"][i][0].get<double>(), -std::sin(t), 1e-7);
    EXPECT_NEAR(file["bodies"][1]["velocity"][i][1].get<double>(), std::cos(t), 1e-7);
  }
}

// The energy error of a massless ship is its specific orbital energy's drift,
// |Δε| / (½v² + GM/r); a ship of tiny mass m has the total energy's, |ΔE| / |E|
// with E = m ε. Both measure the same drift: they agree once the scales are
// converted (|ε| = ½ GM/r and ½v² + GM/r = 3/2 on this orbit: a factor 3).
TEST(NumbersOut, MasslessShipEnergyErrorMatchesATinyMassShip) {
  testing::Engine e;
  json doc = {{"loom", 1}, {"nodes", {{"ship", circular_orbit(0)}, {"tiny", circular_orbit(1e-9)}}}};
  doc["nodes"]["ship"]["inputs"]["velocities"] = {{0, 0, 0}, {0, 1.2, 0}};  // an ellipse: the drift is not 0
  doc["nodes"]["tiny"]["inputs"]["velocities"] = {{0, 0, 0}, {0, 1.2, 0}};
  const double ship = e.output<double>(doc, "ship.energy_error");
  const double tiny = e.output<double>(doc, "tiny.energy_error");
  // ε = ½ 1.44 − 1 = −0.28, scale ½ 1.44 + 1 = 1.72.
  std::printf("massless ship: energy_error %.4g (was always 0); ship of mass 1e-9: %.4g\n", ship, tiny);
  EXPECT_GT(ship, 1e-12);
  EXPECT_NEAR(ship * 1.72 / 0.28, tiny, 1e-6 * tiny);
  const json events = e.output<json>(doc, "ship.events");
  ASSERT_EQ(events["ship_energy_error"].size(), 1u);
  EXPECT_EQ(events["ship_energy_error"][0]["error"].get<double>(), ship);
}

TEST(NumbersOut, ShipsLaunchedFromOnePointAndCoincidentMasses) {
  testing::Engine e;
  const json ships = {{"type", "NBody"},
                      {"inputs",
                       {{"masses", {1.0, 0.0, 0.0, 0.0}},
                        {"positions", {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}}},
                        {"velocities", {{0, 0, 0}, {0, 0.9, 0}, {0, 1.0, 0}, {0, 1.5, 0}}},
                        {"duration", 2.0}}}};
  const json doc = {{"loom", 1}, {"nodes", {{"ships", ships}}}};
  EXPECT_TRUE(e.output<Polylines>(doc, "ships.trajectories").P.allFinite());
  json massive = doc;
  massive["nodes"]["ships"]["inputs"]["masses"] = {1.0, 0.0, 0.1, 0.1};
  Graph g = e.load(massive);
  testing::Run r = e.run(g, {"ships.trajectories"});
  ASSERT_EQ(r.status("ships"), NodeStatus::failed);
  EXPECT_NE(r.error("ships").find("bodies 1 and 2 are at the same position"), std::string::npos) << r.error("ships");
}

// `loom run --target … --json`: the values in full, not cut at 80 characters.
TEST(NumbersOut, RunnerPrintsTargetsAsJsonInFull) {
  const auto dir = test::temp_dir();
  const json doc = {{"loom", 1}, {"nodes", {{"orbit", circular_orbit(0)}}}};
  {
    std::ofstream(dir / "g.json") << doc.dump();
  }
  std::string out;
  ASSERT_EQ(test::run_loom("run " + (dir / "g.json").string() +
                               " --target orbit.table --target orbit.energy_error --target orbit.trajectories --json -q",
                           &out),
            0)
      << out;
  const json printed = json::parse(out.substr(out.find('{')));
  testing::Engine e;
  EXPECT_EQ(printed["orbit.table"], e.output<json>(doc, "orbit.table"));
  EXPECT_EQ(printed["orbit.energy_error"].get<double>(), e.output<double>(doc, "orbit.energy_error"));
  EXPECT_EQ(printed["orbit.trajectories"]["type"], "Polylines");
  EXPECT_GT(printed.dump().size(), 2000u);
}

TEST(NumbersOut, SaveJsonRefusesValuesWithoutAJsonFormAndOtherExtensions) {
  testing::Engine e;
  json doc = {{"loom", 1},
              {"nodes",
               {{"orbit", circular_orbit(0)},
                {"save", {{"type", "SaveJSON"}, {"inputs", {{"value", {{"from", "orbit.trajectories"}}}, {"path", "t.json"}}}}}}}};
  const auto out = test::temp_dir();
  testing::Run r = e.run(doc, {"save"}, out);
  EXPECT_EQ(r.status("save"), NodeStatus::failed);
  EXPECT_NE(r.error("save").find("has no JSON form"), std::string::npos) << r.error("save");
  doc["nodes"]["save"]["inputs"]["value"] = {{"from", "orbit.energy_error"}};
  doc["nodes"]["save"]["inputs"]["path"] = "t.txt";
  r = e.run(doc, {"save"}, out);
  EXPECT_NE(r.error("save").find("writes .json files"), std::string::npos) << r.error("save");
  EXPECT_TRUE(std::filesystem::is_empty(out));
}

}  // namespace
}  // namespace loom
