#pragma once
// Values packed into bytes and read back by the same program: a mesh part sent to its rank
// (parallel/mesh_part.cpp), the model a Gmsh child process hands its parent
// (input/gmsh_child.cpp). Each vector and string goes as its length, then its bytes; a reader
// that runs out of bytes throws std::invalid_argument with the message it was made with.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace hencky {

class ByteWriter {
 public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  /// A vector of plain values (Eigen's fixed-size vectors included: packed doubles).
  template <class T>
  void vector(const std::vector<T>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value(static_cast<std::uint64_t>(s.size()));
    out_ += s;
  }
  void strings(const std::vector<std::string>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    for (const std::string& s : v) string(s);
  }
  const std::string& bytes() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class ByteReader {
 public:
  /// `what` is the message of the std::invalid_argument thrown when the bytes run out.
  ByteReader(std::string_view in, std::string what) : in_(in), what_(std::move(what)) {}
  template <class T>
  void value(T& v) {
    need(sizeof(T));
    std::memcpy(&v, in_.data() + at_, sizeof(T));
    at_ += sizeof(T);
  }
  template <class T>
  void vector(std::vector<T>& v) {
    std::uint64_t n = 0;
    value(n);
    if (n > (in_.size() - at_) / sizeof(T)) fail();
    v.resize(n);
    // Vec3 (Eigen) is a packed triple of doubles, though not trivially copyable by its type.
    if (n) std::memcpy(static_cast<void*>(v.data()), in_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
  }
  void string(std::string& s) {
    std::uint64_t n = 0;
    value(n);
    need(n);
    s.assign(in_.data() + at_, n);
    at_ += n;
  }
  void strings(std::vector<std::string>& v) {
    std::uint64_t n = 0;
    value(n);
    if (n > in_.size() - at_) fail();  // each string takes 8 bytes at least
    v.resize(n);
    for (std::string& s : v) string(s);
  }
  /// A count of things that follow, each at least one byte long.
  std::size_t count() {
    std::uint64_t n = 0;
    value(n);
    if (n > in_.size() - at_) fail();
    return static_cast<std::size_t>(n);
  }
  bool done() const { return at_ == in_.size(); }

 private:
  void need(std::uint64_t n) const {
    if (n > in_.size() - at_) fail();
  }
  [[noreturn]] void fail() const { throw std::invalid_argument(what_); }
  std::string_view in_;
  std::string what_;
  std::size_t at_ = 0;
};

}  // namespace hencky
