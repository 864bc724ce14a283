// "Did you mean": edit distance (swaps included) against hand-worked values, the ranking of
// near names, and the messages a user sees for a mistyped node type or a
// plugin path entry that cannot hold plugins.
#include <algorithm>
#include <fstream>

#include <gtest/gtest.h>

#include "loom/suggest.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

TEST(EditDistance, MatchesHandWorkedExamples) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);  // k->s, e->i, +g
  EXPECT_EQ(edit_distance("flaw", "lawn"), 2u);       // -f, +n
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("Posterize", "posterize"), 0u);  // case does not count
  EXPECT_EQ(edit_distance("Posterise", "Posterize"), 1u);
}

TEST(EditDistance, ASwapOfNeighboursIsOneEdit) {
  // Damerau's optimal string alignment: a transposition counts 1, each letter
  // is edited at most once.
  EXPECT_EQ(edit_distance("rnu", "run"), 1u);
  EXPECT_EQ(edit_distance("vaildate", "validate"), 1u);
  EXPECT_EQ(edit_distance("ab", "ba"), 1u);
  EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // not 2: "ca" -> "ac" -> "abc" edits a swapped letter again
  EXPECT_EQ(edit_distance("abcdef", "badcfe"), 3u);
  EXPECT_EQ(near_names("rnu", {"run", "cache", "validate", "nodes"}), (std::vector<std::string>{"run"}));
}

TEST(NearNames, CaseFirstThenDistanceThenSubstring) {
  const std::vector<std::string> types = {"Checkerboard", "UVCheckerboard", "SaveImage", "SaveMesh",
                                          "LoadImage", "Math"};
  EXPECT_EQ(near_names("checkerboard", types), (std::vector<std::string>{"Checkerboard", "UVCheckerboard"}));
  EXPECT_EQ(near_names("SaveImg", types), (std::vector<std::string>{"SaveImage"}));
  EXPECT_EQ(near_names("Mesh", types), (std::vector<std::string>{"SaveMesh"}));  // contained in it
  EXPECT_TRUE(near_names("Quux", types).empty());
  EXPECT_TRUE(near_names("Math", types).empty());  // itself is not a suggestion
  EXPECT_EQ(near_names("SaveImag", types, 1).size(), 1u);
}

TEST(NearNames, ShortNamesAllowOneEdit) {
  EXPECT_EQ(near_names("Mat", {"Math", "Map", "Mix"}), (std::vector<std::string>{"Map", "Math"}));
}

TEST(UnknownNodeType, SuggestsATypeOfAPluginNotLoaded) {
  // Checkerboard lives in `generate`, which this graph does not load: its
  // manifest supplies the name.
  testing::Engine engine;
  const json doc = {{"loom", 1}, {"nodes", {{"board", {{"type", "checkerbord"}}}}}};
  try {
    engine.load(doc);
    FAIL() << "accepted";
  } catch (const GraphError& e) {
    ASSERT_EQ(e.issues().size(), 1u);
    const std::string& m = e.issues()[0].message;
    EXPECT_NE(m.find("did you mean \"Checkerboard\""), std::string::npos) << m;
    EXPECT_NE(m.find("LOOM_PLUGIN_PATH"), std::string::npos) << m;
  }
  const auto loaded = engine.loaded_plugins();
  EXPECT_EQ(std::find(loaded.begin(), loaded.end(), "generate"), loaded.end());
}

TEST(PluginSearchPath, WarnsAboutMissingFoldersAndFiles) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "libloom_x.so") << "not a folder";
  Registry registry;
  PluginLoader loader(registry, {dir, dir / "missing", dir / "libloom_x.so"});
  const auto warnings = loader.search_path_warnings();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("missing does not exist"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("is a file, not a folder"), std::string::npos) << warnings[1];
}

}  // namespace
}  // namespace loom
