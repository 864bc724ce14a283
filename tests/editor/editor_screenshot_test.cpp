// Screenshots of every example graph: open, evaluate, view the first image,
// capture the framebuffer and check regions (not whole images, which differ
// across Mesa versions): each node's header shows its status colour, links
// are drawn between their sockets, and the viewer shows the image's pixels
// where the viewer says it put them. The PNGs stay in build/editor-screenshots.
#include <algorithm>
#include <cmath>

#include "loom/call_node.hpp"
#include "loom/image.hpp"
#include "ui/canvas.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;

struct Rgb {
  int r, g, b;
};
Rgb pixel(const Rgba8Image& shot, ImVec2 at) {
  const int x = std::clamp(int(at.x), 0, shot.width - 1), y = std::clamp(int(at.y), 0, shot.height - 1);
  const std::uint8_t* p = shot.at(x, y);
  return {p[0], p[1], p[2]};
}
int difference(Rgb a, ImU32 c) {
  const ImVec4 f = ImGui::ColorConvertU32ToFloat4(c);
  return std::max({std::abs(a.r - int(f.x * 255 + 0.5f)), std::abs(a.g - int(f.y * 255 + 0.5f)),
                   std::abs(a.b - int(f.z * 255 + 0.5f))});
}
// Whether a colour close to `c` is within `radius` pixels of `at`.
bool near_color(const Rgba8Image& shot, ImVec2 at, ImU32 c, int radius, int tolerance) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (difference(pixel(shot, ImVec2(at.x + dx, at.y + dy)), c) <= tolerance) return true;
  return false;
}

ImVec2 bezier_middle(ImVec2 a, ImVec2 b, float zoom) {
  const float dx = std::max(40.0f * zoom, std::abs(b.x - a.x) * 0.5f);
  const ImVec2 c1(a.x + dx, a.y), c2(b.x - dx, b.y);
  return {(a.x + 3 * c1.x + 3 * c2.x + b.x) / 8, (a.y + 3 * c1.y + 3 * c2.y + b.y) / 8};
}

std::uint8_t displayed(float v, Encoding e) {
  if (e == Encoding::linear) v = linear_to_srgb(std::max(0.0f, v));
  return std::uint8_t(std::clamp(v, 0.0f, 1.0f) * 255 + 0.5f);
}

std::vector<fs::path> example_graphs() {
  std::vector<fs::path> graphs;
  for (const auto& e : fs::directory_iterator(fs::path(LOOM_SOURCE_DIR) / "graphs"))
    if (e.path().extension() == ".json" && e.path().string().find(".coursedata.") == std::string::npos)
      graphs.push_back(e.path());
  std::sort(graphs.begin(), graphs.end());
  return graphs;
}

class ExampleGraph : public ::testing::TestWithParam<fs::path> {};

TEST_P(ExampleGraph, ScreenshotShowsNodesLinksAndImage) {
  Harness h(1400, 820);
  h.app.open(GetParam());
  h.frame(2);
  ASSERT_TRUE(h.settle(240)) << "evaluation did not finish";
  auto& state = h.app.state();
  ASSERT_TRUE(state.issues.empty()) << state.issues.begin()->second.begin()->second;
  GraphDocument& doc = h.app.document();

  // View the first node with an Image output that ran.
  std::string viewed;
  for (const auto& id : doc.node_ids()) {
    const NodeType* t = doc.node_type(id);
    const NodeReport* r = state.report(id);
    if (!t || !r || (r->status != NodeStatus::ran && r->status != NodeStatus::cached)) continue;
    const ImVec2 header = h.app.canvas().node_header(state, id);
    const bool visible = header.x > 10 && header.y > 60 && header.x < 1400 * 0.58f - 10 && header.y < 810;
    if (visible && !t->spec.outputs.empty() && t->spec.outputs[0].type == &loom::type_of<loom::Image>()) {
      viewed = id;
      break;
    }
  }
  if (!viewed.empty()) {
    h.click(h.app.canvas().node_header(state, viewed));
    ASSERT_EQ(state.viewed, viewed);
    ASSERT_TRUE(h.settle(240));
  }
  h.jump({600, 815});  // no hover, no tooltip
  const std::string name = GetParam().stem().string();
  const Rgba8Image shot = h.screenshot("graph-" + name);
  Canvas& canvas = h.app.canvas();

  // Frame-all shrinks a large graph until headers are a few pixels tall: the
  // header and link colours are checked only where they are large enough.
  const bool sample_canvas = canvas.zoom() >= 0.5f;

  // Node headers in their status colour (sinks are pruned: not evaluated in preview).
  int headers = 0, headers_ok = 0;
  for (const auto& id : doc.node_ids()) {
    const ImVec2 a = canvas.to_screen(doc.position(id));
    const ImVec2 probe(a.x + 100 * canvas.zoom(), a.y + 2.5f * canvas.zoom());
    if (probe.x < 5 || probe.y < 40 || probe.x > shot.width * 0.58f - 5 || probe.y > shot.height - 5) continue;
    const NodeReport* r = state.report(id);
    ImU32 expected = IM_COL32(70, 70, 78, 255);
    if (r && r->status == NodeStatus::ran) expected = IM_COL32(60, 150, 80, 255);
    if (r && r->status == NodeStatus::cached) expected = IM_COL32(60, 110, 170, 255);
    ++headers;
    if (near_color(shot, probe, expected, 1, 12)) ++headers_ok;
  }
  if (sample_canvas) {
    EXPECT_GT(headers, 0);
    // Another node may lie over a header; most must show.
    EXPECT_GE(headers_ok * 10, headers * 8) << headers_ok << " of " << headers << " headers";
  }

  // Links: the curve's midpoint carries the type's colour (unless a node covers it).
  int links = 0, links_ok = 0;
  for (const auto& id : doc.node_ids()) {
    const NodeType* t = doc.node_type(id);
    if (!t) continue;
    for (const auto& in : t->spec.inputs) {
      auto l = doc.link(id, in.name);
      if (!l) continue;
      const ImVec2 mid = bezier_middle(*canvas.output_socket(state, l->node, l->output),
                                       *canvas.input_socket(state, id, in.name), canvas.zoom());
      if (mid.x < 5 || mid.y < 40 || mid.x > shot.width * 0.58f - 5 || mid.y > shot.height - 5) continue;
      if (!canvas.hit_node(state, mid).empty()) continue;  // links run under nodes
      ++links;
      if (near_color(shot, mid, type_color(*in.type), 3, 40)) ++links_ok;
    }
  }
  if (sample_canvas) {
    EXPECT_GE(links_ok * 10, links * 6) << links_ok << " of " << links << " links";
  }

  // The viewer: sampled pixels of the image are where the viewer drew them.
  if (viewed.empty()) return;
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0);
  Image image = state.viewed_output(0).as<Image>();
  if (!image.space.empty()) {  // shown through the display's default view (ColorConvert's ACEScg)
    NodeCall call;
    call.values.emplace("image", state.viewed_output(0));
    image = call_node(*h.app.registry().find("DisplayView"), call).at(0).as<Image>();
  }
  const int c = image.channels();
  const int reach = int(std::ceil(1.0f / view.scale)) + 1;
  int samples = 0, samples_ok = 0;
  for (int sy = 1; sy <= 7; ++sy)
    for (int sx = 1; sx <= 7; ++sx) {
      const int x = image.width() * sx / 8, y = image.height() * sy / 8;
      // The displayed value may blend neighbours (minification): accept the
      // range of the footprint around the sample.
      int lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0};
      for (int yy = std::max(0, y - reach); yy <= std::min(image.height() - 1, y + reach); ++yy)
        for (int xx = std::max(0, x - reach); xx <= std::min(image.width() - 1, x + reach); ++xx) {
          const float* px = image.pixels.ptr<float>(yy) + std::size_t(xx) * c;
          for (int k = 0; k < 3; ++k) {
            const int v = displayed(px[c >= 3 ? k : 0], image.encoding);
            lo[k] = std::min(lo[k], v);
            hi[k] = std::max(hi[k], v);
          }
        }
      const Rgb got = pixel(shot, view.to_screen(x + 0.5, y + 0.5));
      const int g[3] = {got.r, got.g, got.b};
      bool ok = true;
      for (int k = 0; k < 3; ++k) ok = ok && g[k] >= lo[k] - 6 && g[k] <= hi[k] + 6;
      ++samples;
      if (ok) ++samples_ok;
    }
  EXPECT_GE(samples_ok * 10, samples * 9) << samples_ok << " of " << samples << " image samples";
}

INSTANTIATE_TEST_SUITE_P(Graphs, ExampleGraph, ::testing::ValuesIn(example_graphs()),
                         [](const auto& info) {
                           std::string n = info.param.stem().string();
                           std::replace_if(n.begin(), n.end(), [](char ch) { return !std::isalnum(ch); }, '_');
                           return n;
                         });

}  // namespace
}  // namespace loom::editor::test
