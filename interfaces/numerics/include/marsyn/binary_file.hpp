#pragma once
// Versioned, checksummed binary files for plugins' artefacts (controllers): an 8-byte magic, a
// u32 format version, a u64 payload size, the payload, and the payload's u64 FNV-1a hash, all
// little-endian so that a file does not depend on the host. Readers name the file and the defect.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace marsyn::binary {

inline std::uint64_t fnv1a(const char* p, std::size_t len) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < len; ++i) {
    h ^= static_cast<unsigned char>(p[i]);
    h *= 1099511628211ull;
  }
  return h;
}

class Writer {
 public:
  void u8(std::uint8_t v) { s_.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    u64(b);
  }
  void str(const std::string& v) {
    u32(static_cast<std::uint32_t>(v.size()));
    s_ += v;
  }
  void reals(const std::vector<double>& v) {
    for (double x : v) f64(x);
  }
  std::string& bytes() { return s_; }

 private:
  std::string s_;
};

class Reader {
 public:
  Reader(const std::string& s, std::size_t begin, std::size_t end, std::string what)
      : s_(s), p_(begin), end_(end), what_(std::move(what)) {}
  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error(what_ + ": " + why); }
  void need(std::size_t k) const {
    if (end_ - p_ < k) fail("truncated payload");
  }
  std::uint8_t u8() {
    need(1);
    return static_cast<std::uint8_t>(s_[p_++]);
  }
  std::uint64_t uN(int bytes) {
    need(static_cast<std::size_t>(bytes));
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(s_[p_++])) << (8 * i);
    return v;
  }
  std::uint16_t u16() { return static_cast<std::uint16_t>(uN(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(uN(4)); }
  std::int64_t i64() { return static_cast<std::int64_t>(uN(8)); }
  double f64() {
    const std::uint64_t b = uN(8);
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
  std::string str(std::size_t max_len = 4096) {
    const std::uint32_t len = u32();
    if (len > max_len) fail("string of " + std::to_string(len) + " bytes");
    need(len);
    std::string v = s_.substr(p_, len);
    p_ += len;
    return v;
  }
  std::vector<double> reals(std::size_t count) {
    need(8 * count);
    std::vector<double> v(count);
    for (auto& x : v) x = f64();
    return v;
  }
  bool done() const { return p_ == end_; }

 private:
  const std::string& s_;
  std::size_t p_, end_;
  std::string what_;
};

// The whole file for `payload`.
inline std::string envelope(const char (&magic)[8], std::uint32_t version, const std::string& payload) {
  Writer f;
  for (char c : magic) f.u8(static_cast<std::uint8_t>(c));
  f.u32(version);
  f.u64(payload.size());
  f.bytes() += payload;
  f.u64(fnv1a(payload.data(), payload.size()));
  return std::move(f.bytes());
}

// Checks magic, size and checksum; returns the format version and sets [begin, end) of the
// payload. `kind` names the expected content in the messages ("a marsyn funnel controller").
inline std::uint32_t open_envelope(const std::string& s, const char (&magic)[8], const std::string& what,
                                   const std::string& kind, std::size_t& begin, std::size_t& end) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(what + ": " + why); };
  if (s.size() < 8 || std::memcmp(s.data(), magic, 8) != 0) fail("not " + kind + " (bad magic)");
  if (s.size() < 28) fail("truncated header");
  Reader h(s, 8, s.size(), what);
  const std::uint32_t version = h.u32();
  const std::uint64_t size = h.uN(8);
  if (size != s.size() - 28) fail("truncated or oversized (payload size does not match file size)");
  Reader t(s, 20 + size, s.size(), what);
  if (t.uN(8) != fnv1a(s.data() + 20, size)) fail("checksum mismatch (corrupt file)");
  begin = 20;
  end = 20 + size;
  return version;
}

}  // namespace marsyn::binary
