#pragma once
// Plain byte encoding of the values ranks exchange (plans, tracking outcomes, verification runs):
// fixed-size values as their bytes (the ranks of one run share the machine type), strings and
// vectors with a length first. Doubles travel bit for bit, so every rank sees the same numbers.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

namespace marsyn::mpi {

class ByteWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T> void put(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof v);
  }
  void put(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  void put(const std::vector<std::uint8_t>& b) {
    put<std::uint64_t>(b.size());
    bytes_.insert(bytes_.end(), b.begin(), b.end());
  }
  void put(const Eigen::VectorXd& v) {
    put<std::uint64_t>(static_cast<std::uint64_t>(v.size()));
    for (Eigen::Index i = 0; i < v.size(); ++i) put(v[i]);
  }
  template <class T>
  void put(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    for (const T& x : v) put(x);
  }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::vector<std::uint8_t>& b) : b_(b) {}
  template <class T>
  requires std::is_trivially_copyable_v<T> void get(T& v) {
    need(sizeof v);
    std::memcpy(&v, b_.data() + at_, sizeof v);
    at_ += sizeof v;
  }
  void get(std::string& s) {
    const std::uint64_t n = count();
    need(n);
    s.assign(reinterpret_cast<const char*>(b_.data() + at_), n);
    at_ += n;
  }
  void get(std::vector<std::uint8_t>& v) {
    const std::uint64_t n = count();
    need(n);
    v.assign(b_.begin() + static_cast<std::ptrdiff_t>(at_), b_.begin() + static_cast<std::ptrdiff_t>(at_ + n));
    at_ += n;
  }
  void get(Eigen::VectorXd& v) {
    const std::uint64_t n = count();
    v.resize(static_cast<Eigen::Index>(n));
    for (Eigen::Index i = 0; i < v.size(); ++i) get(v[i]);
  }
  template <class T>
  void get(std::vector<T>& v) {
    v.resize(count());
    for (T& x : v) get(x);
  }
  bool done() const { return at_ == b_.size(); }

 private:
  std::uint64_t count() {
    std::uint64_t n = 0;
    get(n);
    if (n > b_.size()) throw std::runtime_error("a rank sent a malformed message (length beyond its end)");
    return n;
  }
  void need(std::size_t n) const {
    if (at_ + n > b_.size()) throw std::runtime_error("a rank sent a truncated message");
  }
  const std::vector<std::uint8_t>& b_;
  std::size_t at_ = 0;
};

}  // namespace marsyn::mpi
