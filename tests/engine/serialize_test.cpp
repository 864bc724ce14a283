// Round trips of every storable type through its TypeInfo (the path the disk
// cache takes), compared field by field with the original; every truncation
// of a written value is refused.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/point_pairs.hpp"
#include "loom/point_set.hpp"
#include "loom/polylines.hpp"

namespace loom {
namespace {

// Writes through the type-erased TypeInfo and reads back; also checks that
// every proper prefix of the bytes is refused with an Error.
template <class T>
T round_trip(const T& value) {
  const TypeInfo& info = type_of<T>();
  EXPECT_TRUE(info.storable()) << info.name;
  EXPECT_GE(info.serial_version, 1);
  ByteWriter w;
  info.write(&value, w);
  const auto& b = w.buffer();
  for (std::size_t n = 0; n < b.size(); n += 1 + b.size() / 97) {
    ByteReader t(b.data(), n);
    EXPECT_THROW(info.read(t), Error) << info.name << " truncated to " << n << " of " << b.size();
  }
  ByteReader r(b.data(), b.size());
  auto back = info.read(r);
  EXPECT_TRUE(r.at_end()) << info.name;
  return *static_cast<const T*>(back.get());
}

TEST(Serialize, BuiltinTypesRoundTrip) {
  EXPECT_EQ(round_trip(true), true);
  EXPECT_EQ(round_trip(false), false);
  EXPECT_EQ(round_trip(-123456), -123456);
  EXPECT_EQ(round_trip(0.1 + 0.2), 0.1 + 0.2);
  EXPECT_EQ(round_trip(std::string("héllo\nworld")), "héllo\nworld");
  EXPECT_EQ(round_trip(std::string()), "");
  EXPECT_EQ(round_trip(Vec2i(3, -4)), Vec2i(3, -4));
  EXPECT_EQ(round_trip(Vec2(0.5, 1e300)), Vec2(0.5, 1e300));
  EXPECT_EQ(round_trip(Vec3i(1, 2, 3)), Vec3i(1, 2, 3));
  EXPECT_EQ(round_trip(Vec3(-0.0, 2.5, 3)), Vec3(-0.0, 2.5, 3));
  EXPECT_EQ(round_trip(Color{{0.1, 0.2, 0.3, 0.4}}).rgba, Eigen::Vector4d(0.1, 0.2, 0.3, 0.4));
  EXPECT_EQ(round_trip(std::vector<int>{1, -2, 3}), (std::vector<int>{1, -2, 3}));
  EXPECT_EQ(round_trip(std::vector<double>{}), std::vector<double>{});
  EXPECT_EQ(round_trip(std::vector<double>{0.25, -7}), (std::vector<double>{0.25, -7}));
  EXPECT_EQ(round_trip(std::vector<std::string>{"a", "", "ccc"}), (std::vector<std::string>{"a", "", "ccc"}));
  EXPECT_EQ(round_trip(std::vector<Vec2>{{1, 2}, {3, 4}}), (std::vector<Vec2>{{1, 2}, {3, 4}}));
  EXPECT_EQ(round_trip(std::vector<Vec3>{{1, 2, 3}}), (std::vector<Vec3>{{1, 2, 3}}));
  const json j = {{"a", {1, 2.5, "x"}}, {"b", nullptr}, {"c", {{"d", true}}}};
  EXPECT_EQ(round_trip(j), j);
  PointPairs pp;
  pp.p = {{1, 2}, {3, 4}};
  pp.q = {{5, 6}, {7, 8}};
  const PointPairs back = round_trip(pp);
  EXPECT_EQ(back.p, pp.p);
  EXPECT_EQ(back.q, pp.q);
}

TEST(Serialize, ImageRoundTripKeepsPixelsChannelsEncodingAndColourSpace) {
  for (int ch = 1; ch <= 4; ++ch) {
    Image image(cv::Mat(7, 5, CV_MAKETYPE(CV_32F, ch)), ch % 2 ? Encoding::srgb : Encoding::linear,
                ch == 3 ? "ACEScg" : "");
    cv::randu(image.pixels, -1.0, 2.0);
    const Image back = round_trip(image);
    EXPECT_EQ(back.width(), 5);
    EXPECT_EQ(back.height(), 7);
    EXPECT_EQ(back.channels(), ch);
    EXPECT_EQ(back.encoding, image.encoding);
    EXPECT_EQ(back.space, image.space);
    EXPECT_EQ(cv::norm(back.pixels, image.pixels, cv::NORM_INF), 0.0);
    EXPECT_EQ(type_of<Image>().bytes(&image), 7u * 5u * static_cast<unsigned>(ch) * sizeof(float));
  }
  // A region of a larger image (non-contiguous rows) is written as its own pixels.
  cv::Mat big(10, 10, CV_32FC3);
  cv::randu(big, 0.0, 1.0);
  Image roi(big(cv::Rect(2, 3, 4, 5)), Encoding::linear);
  EXPECT_EQ(cv::norm(round_trip(roi).pixels, roi.pixels, cv::NORM_INF), 0.0);
  EXPECT_TRUE(round_trip(Image()).empty());
}

TEST(Serialize, MeshPointSetAndPolylinesRoundTrip) {
  Mesh m;
  m.V = Eigen::MatrixX3d::Random(6, 3);
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 3, 4, 5;
  m.UV = Eigen::MatrixX2d::Random(6, 2);
  m.C = Eigen::MatrixX3d::Random(6, 3);  // no normals: stays empty
  const Mesh mb = round_trip(m);
  EXPECT_EQ(mb.V, m.V);
  EXPECT_EQ(mb.F, m.F);
  EXPECT_EQ(mb.UV, m.UV);
  EXPECT_EQ(mb.N.rows(), 0);
  EXPECT_EQ(mb.C, m.C);

  PointSet p;
  p.P = Eigen::MatrixX3d::Random(100, 3);
  p.radius = Eigen::VectorXd::Random(100).cwiseAbs();
  const PointSet pb = round_trip(p);
  EXPECT_EQ(pb.P, p.P);
  EXPECT_EQ(pb.radius, p.radius);
  EXPECT_EQ(pb.C.rows(), 0);
  EXPECT_EQ(type_of<PointSet>().bytes(&p), 400u * sizeof(double));

  Polylines l;
  l.P = Eigen::MatrixX3d::Random(4, 3);
  l.E.resize(3, 2);
  l.E << 0, 1, 1, 2, 2, 3;
  l.C = Eigen::MatrixX3d::Random(4, 3);
  const Polylines lb = round_trip(l);
  EXPECT_EQ(lb.P, l.P);
  EXPECT_EQ(lb.E, l.E);
  EXPECT_EQ(lb.C, l.C);
}

}  // namespace
}  // namespace loom
