// Multi-layer and multi-part EXR, half and tiled files, and the provenance in
// every header, each checked by a reader that is not Loom's: OpenEXR's own
// library for values, oiiotool and exrheader for what a file declares.
#include <filesystem>
#include <fstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "image_codec.hpp"
#include "noise_image.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

Image noise(int channels, float low, float high, int seed) {
  return test::noise_image(24, 40, channels, low, high, seed);
}

std::vector<io::NamedImage> aovs() {
  return {{"image", noise(3, 0, 8, 1), {"R", "G", "B", "A"}},
          {"albedo", noise(3, 0, 1, 2), {"R", "G", "B"}},
          {"normal", noise(3, -1, 1, 3), {"X", "Y", "Z"}},
          {"depth", noise(1, 0, 50, 4), {"Z"}}};
}

// One channel of an EXR part through OpenEXR's own reader, as floats.
cv::Mat exr_channel(Imf::InputPart& part, const std::string& name) {
  const Imath::Box2i window = part.header().dataWindow();
  cv::Mat plane(window.max.y - window.min.y + 1, window.max.x - window.min.x + 1, CV_32F);
  Imf::FrameBuffer buffer;
  buffer.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(plane.data), sizeof(float),
                                 sizeof(float) * static_cast<std::size_t>(plane.cols)));
  part.setFrameBuffer(buffer);
  part.readPixels(window.min.y, window.max.y);
  return plane;
}

double difference(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

std::string oiiotool_info(const fs::path& file) {
  std::string out;
  if (test::run_shell("oiiotool --info -v " + file.string(), &out) != 0) return {};
  return out;
}

TEST(ImageLayers, OneExrWithNamedLayersAsBlenderAndNukeReadThem) {
  const fs::path dir = test::temp_dir();
  const auto layers = aovs();
  io::write_layers(layers, dir / "aov.exr", false, false, false, {{"loom:node", "save"}});
  // OpenEXR's reader: one part, channels "<layer>.<channel>", values exact.
  Imf::MultiPartInputFile file((dir / "aov.exr").c_str());
  ASSERT_EQ(file.parts(), 1);
  Imf::InputPart part(file, 0);
  for (const auto& l : layers) {
    std::vector<cv::Mat> planes;
    cv::split(l.image.pixels, planes);
    for (std::size_t c = 0; c < planes.size(); ++c) {
      const std::string name = l.name + "." + l.channels[c];
      ASSERT_NE(part.header().channels().findChannel(name), nullptr) << name;
      EXPECT_EQ(part.header().channels().findChannel(name)->type, Imf::FLOAT) << name;
      EXPECT_EQ(difference(exr_channel(part, name), planes[c]), 0.0) << name;
    }
  }
  EXPECT_EQ(part.header().channels().findChannel("image.A"), nullptr);  // 3 channels: no alpha written
  // oiiotool lists the layers' channels.
  const std::string info = oiiotool_info(dir / "aov.exr");
  if (info.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed";
  for (const char* name : {"image.R", "albedo.G", "normal.X", "normal.Z", "depth.Z", "loom:node: \"save\""})
    EXPECT_NE(info.find(name), std::string::npos) << name << " not in\n" << info;
}

TEST(ImageLayers, LoadImageReadsALayerByNameAndRefusesToGuess) {
  const fs::path dir = test::temp_dir();
  const auto layers = aovs();
  io::write_layers(layers, dir / "aov.exr", false, false, false, {});
  for (const auto& l : layers) {
    const Image back = io::read_image(dir / "aov.exr", io::Decode::linear, io::kDefaultMaxImagePixels, l.name);
    EXPECT_EQ(back.encoding, Encoding::linear);
    ASSERT_EQ(back.channels(), l.image.channels()) << l.name;
    EXPECT_EQ(difference(back.pixels, l.image.pixels), 0.0) << l.name;
  }
  for (const std::string layer : {"", "specular"}) {
    try {
      io::read_image(dir / "aov.exr", io::Decode::linear, io::kDefaultMaxImagePixels, layer);
      FAIL() << layer;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("albedo, depth, image, normal"), std::string::npos) << e.what();
    }
  }
}

TEST(ImageLayers, MultiPartHalfAndTiled) {
  const fs::path dir = test::temp_dir();
  const auto layers = aovs();
  io::write_layers(layers, dir / "parts.exr", true, true, true, {});
  Imf::MultiPartInputFile file((dir / "parts.exr").c_str());
  ASSERT_EQ(file.parts(), 4);
  for (int p = 0; p < file.parts(); ++p) {
    const auto& l = layers[static_cast<std::size_t>(p)];
    EXPECT_EQ(file.header(p).name(), l.name);
    EXPECT_TRUE(file.header(p).hasTileDescription()) << l.name;
    Imf::InputPart part(file, p);
    std::vector<cv::Mat> planes;
    cv::split(l.image.pixels, planes);
    const std::string first = l.name + "." + l.channels[0];
    ASSERT_NE(part.header().channels().findChannel(first), nullptr) << first;
    EXPECT_EQ(part.header().channels().findChannel(first)->type, Imf::HALF);
    // Half keeps 11 significant bits: within 2^-11 relative.
    const cv::Mat tolerance = cv::abs(planes[0]) * (1.0 / 2048) + 1e-7;
    cv::Mat excess = cv::abs(exr_channel(part, first) - planes[0]) - tolerance;
    EXPECT_LE(cv::norm(cv::max(excess, 0), cv::NORM_INF), 0.0) << first;
    // LoadImage finds the part by its name.
    const Image back = io::read_image(dir / "parts.exr", io::Decode::linear, io::kDefaultMaxImagePixels, l.name);
    ASSERT_EQ(back.channels(), l.image.channels());
  }
}

// A channel set Loom has no order for is refused, not guessed at.
TEST(ImageLayers, ChannelsInNoKnownOrderAreRefused) {
  const fs::path dir = test::temp_dir();
  std::string out;
  if (test::run_shell("oiiotool --create 8x8 5 -d float -o " + (dir / "five.exr").string() +
                          " && oiiotool --create 8x8 2 --chnames R,G -d float -o " + (dir / "rg.exr").string(),
                      &out) != 0)
    GTEST_SKIP() << "oiiotool (openimageio-tools) cannot make the files: " << out;
  for (const char* name : {"five.exr", "rg.exr"}) {
    try {
      io::read_image(dir / name, io::Decode::linear);
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("no order Loom reads"), std::string::npos) << e.what();
    }
  }
}

// Every file SaveImage and SaveLayers write names the node, its seed and the
// frame in its header; `loom info` prints them back, as does oiiotool.
TEST(ImageLayers, EveryHeaderSaysWhichNodeMadeIt) {
  const fs::path dir = test::temp_dir();
  std::ofstream(dir / "g.json") << R"({"loom": 1, "seed": 5, "time": {"start": 3, "end": 3, "fps": 24}, "nodes": {
    "board": {"type": "Checkerboard", "inputs": {"size": [32, 16]}},
    "png": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "b.png"}},
    "tif": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "b.tif", "depth": "16"}},
    "jpg": {"type": "SaveImage", "inputs": {"image": {"from": "board.image"}, "path": "b.jpg"}},
    "exr": {"type": "SaveImage",
            "inputs": {"image": {"from": "board.image"}, "path": "b.exr", "depth": "half", "tiled": true}},
    "layers": {"type": "SaveLayers",
               "inputs": {"image": {"from": "board.image"}, "albedo": {"from": "board.image"}, "path": "l.exr"}}}})";
  std::string out;
  ASSERT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out), 0) << out;
  for (const std::string node : {"png", "tif", "jpg", "exr", "layers"}) {
    const std::string file = node == "layers" ? "l.exr" : "b." + node;
    ASSERT_EQ(test::run_loom("info " + (dir / "out" / file).string(), &out), 0) << out;
    EXPECT_NE(out.find("Loom: node " + node + ", seed "), std::string::npos) << file << ":\n" << out;
    EXPECT_NE(out.find(", frame 3"), std::string::npos) << file << ":\n" << out;
  }
  ASSERT_EQ(test::run_loom("info " + (dir / "out" / "l.exr").string(), &out), 0);
  EXPECT_NE(out.find("layer albedo: R (float) G (float) B (float)"), std::string::npos) << out;
  EXPECT_NE(out.find("loom:node: \"layers\""), std::string::npos) << out;
  ASSERT_EQ(test::run_loom("info " + (dir / "out" / "b.exr").string(), &out), 0);
  EXPECT_NE(out.find("tiles 64x64"), std::string::npos) << out;
  EXPECT_NE(out.find("R (half)"), std::string::npos) << out;
  EXPECT_EQ(test::run_loom("info " + (dir / "g.json").string(), &out), 2) << out;
  const std::string info = oiiotool_info(dir / "out" / "b.png");
  if (info.empty()) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed";
  EXPECT_NE(info.find("loom:node: \"png\""), std::string::npos) << info;
}

// OpenCV's codecs (libpng, libtiff, libjpeg: not OpenImageIO's readers) read
// back exactly what was written: 8/16-bit values as quantized, and colour
// under a transparent or half-transparent alpha untouched (OpenImageIO
// divides colour by alpha on writing unless told the alpha is unassociated).
TEST(ImageFiles, AnotherReaderFindsTheValuesAndTheAlphaAsStored) {
  const fs::path dir = test::temp_dir();
  Image rgba = noise(4, 0, 1, 8);
  rgba.encoding = Encoding::srgb;
  rgba.pixels.at<cv::Vec4f>(2, 3)[3] = 0.0f;  // transparent: its colour must survive
  rgba.pixels.at<cv::Vec4f>(5, 7)[3] = 0.5f;
  struct Case {
    const char* name;
    io::Depth depth;
    int cv_depth;
    double scale;
  };
  for (const Case& c : {Case{"a.png", io::Depth::u8, CV_8U, 255}, Case{"a.tif", io::Depth::u16, CV_16U, 65535},
                        Case{"b.png", io::Depth::u16, CV_16U, 65535}}) {
    io::write_image(rgba, dir / c.name, c.depth);
    cv::Mat read = cv::imread((dir / c.name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(read.type(), CV_MAKETYPE(c.cv_depth, 4)) << c.name;
    cv::cvtColor(read, read, cv::COLOR_BGRA2RGBA);
    cv::Mat expected;
    rgba.pixels.convertTo(expected, c.cv_depth, c.scale);
    EXPECT_EQ(cv::norm(read, expected, cv::NORM_INF), 0.0) << c.name;
  }
}

// Two writes a second apart give the same bytes: no time of writing in a header.
TEST(ImageLayers, FilesHoldNoTimeOfWriting) {
  const fs::path dir = test::temp_dir();
  const Image image = noise(4, 0, 1, 7);
  const std::vector<std::string> names = {"a.exr", "a.png", "a.tif", "a.jpg"};
  for (const char* run : {"first", "second"}) {
    for (const auto& name : names)
      io::write_image(image, dir / run / name, name == "a.exr" ? io::Depth::f32 : io::Depth::u8, {{"loom:node", "n"}});
    std::string out;
    test::run_shell("sleep 1.1", &out);
  }
  for (const auto& name : names) {
    std::ifstream a(dir / "first" / name, std::ios::binary), b(dir / "second" / name, std::ios::binary);
    const std::string x((std::istreambuf_iterator<char>(a)), {}), y((std::istreambuf_iterator<char>(b)), {});
    EXPECT_TRUE(!x.empty() && x == y) << name;
  }
}

}  // namespace
}  // namespace loom
