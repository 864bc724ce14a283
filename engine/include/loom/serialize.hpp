// Plugin author API. Binary serialization of values, for the persistent result cache.
//
// A type that can be stored on disk gives its TypeTraits two functions:
//
//   static void write(const T& v, loom::ByteWriter& w);
//   static T read(loom::ByteReader& r);   // throws loom::Error on bad data
//
// A type without them is simply never stored. The format is the type's own
// business: little-endian PODs and Eigen/OpenCV buffers written as they are in
// memory, each prefixed by its sizes. The cache adds the envelope (type name,
// type version, checksum), so read() may assume the bytes were written by
// write() of the same build, but must still never read past the end (a
// truncated file is detected by the checksum first; the bound is a second net).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "loom/error.hpp"

namespace loom {

class ByteWriter {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const char*>(data);
    buffer_.insert(buffer_.end(), p, p + n);
  }
  template <class T, class = std::enable_if_t<std::is_trivially_copyable_v<T>>>
  void pod(const T& v) { bytes(&v, sizeof v); }
  void str(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  // Rows, columns, then the coefficients in Eigen's storage order.
  template <class Derived>
  void matrix(const Eigen::PlainObjectBase<Derived>& m) {
    using Scalar = typename Derived::Scalar;
    pod<std::int64_t>(m.rows());
    pod<std::int64_t>(m.cols());
    bytes(m.data(), sizeof(Scalar) * static_cast<std::size_t>(m.size()));
  }
  template <class T>
  void vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod<std::uint64_t>(v.size());
    bytes(v.data(), sizeof(T) * v.size());
  }

  const std::vector<char>& buffer() const { return buffer_; }
  std::vector<char>& buffer() { return buffer_; }

 private:
  std::vector<char> buffer_;
};

class ByteReader {
 public:
  ByteReader(const char* data, std::size_t size) : p_(data), end_(data + size) {}

  void bytes(void* out, std::size_t n) {
    if (n > remaining()) throw Error("stored value is truncated");
    if (n == 0) return;  // an empty array's data() may be null: memcpy(null, ..., 0) is UB
    std::memcpy(out, p_, n);
    p_ += n;
  }
  template <class T, class = std::enable_if_t<std::is_trivially_copyable_v<T>>>
  T pod() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  std::string str() {
    const auto n = count(1);
    std::string s(n, '\0');
    bytes(s.data(), n);
    return s;
  }
  template <class M>
  M matrix() {
    using Scalar = typename M::Scalar;
    const auto rows = pod<std::int64_t>(), cols = pod<std::int64_t>();
    if (rows < 0 || cols < 0 ||
        (M::RowsAtCompileTime != Eigen::Dynamic && rows != M::RowsAtCompileTime) ||
        (M::ColsAtCompileTime != Eigen::Dynamic && cols != M::ColsAtCompileTime) ||
        (rows > 0 && static_cast<std::uint64_t>(cols) >
                         remaining() / sizeof(Scalar) / static_cast<std::uint64_t>(rows)))
      throw Error("stored matrix has impossible dimensions");
    M m(rows, cols);
    bytes(m.data(), sizeof(Scalar) * static_cast<std::size_t>(m.size()));
    return m;
  }
  template <class T>
  std::vector<T> vector() {
    std::vector<T> v(count(sizeof(T)));
    bytes(v.data(), sizeof(T) * v.size());
    return v;
  }

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  bool at_end() const { return p_ == end_; }

 private:
  // An element count that the remaining bytes can hold.
  std::size_t count(std::size_t element_size) {
    const auto n = pod<std::uint64_t>();
    if (element_size > 0 && n > remaining() / element_size)
      throw Error("stored value is truncated");
    return static_cast<std::size_t>(n);
  }
  const char* p_;
  const char* end_;
};

}  // namespace loom
