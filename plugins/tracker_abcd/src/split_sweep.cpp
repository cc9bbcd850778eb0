#include "split_sweep.hpp"

#include <cstring>
#include <stdexcept>

namespace marsyn::abcd {

std::int64_t SweepSplit::exchange_winning(const IndexBox& bk, const std::uint16_t* inputs, std::uint16_t losing,
                                          std::vector<std::uint8_t>& win) const {
  const std::int64_t cells = bk.size();
  win.assign(static_cast<size_t>(cells), 0);
  std::vector<bool> bits;
  cells_of(bk, rank_, [&](std::int64_t l) {
    const bool w = inputs[l] != losing;
    bits.push_back(w);
    win[static_cast<size_t>(l)] = w ? 1 : 0;
  });
  if (!split()) return 0;
  const std::vector<std::uint8_t> mine = pack_bits(bits);
  const auto all = c_->allgather(mine);
  if (static_cast<int>(all.size()) != ranks_) throw std::runtime_error("abcd: the rank group returned a wrong allgather");
  for (int q = 0; q < ranks_; ++q) {
    if (q == rank_) continue;
    std::size_t at = 0;
    cells_of(bk, q, [&](std::int64_t l) {
      if (bit_at(all[static_cast<size_t>(q)], at++)) win[static_cast<size_t>(l)] = 1;
    });
    if ((at + 7) / 8 != all[static_cast<size_t>(q)].size())
      throw std::runtime_error("abcd: rank " + std::to_string(q) + " sent a winning set of another size");
  }
  return static_cast<std::int64_t>(mine.size());
}

std::int64_t SweepSplit::exchange_inputs(const std::vector<IndexBox>& boxes, const std::vector<std::int64_t>& offsets,
                                         int first, int last, std::vector<std::uint16_t>& inputs) const {
  if (!split() || first > last) return 0;
  std::vector<std::uint8_t> mine;
  for (int k = first; k <= last; ++k) {
    const std::int64_t off = offsets[static_cast<size_t>(k)];
    cells_of(boxes[static_cast<size_t>(k)], rank_, [&](std::int64_t l) {
      const std::uint16_t j = inputs[static_cast<size_t>(off + l)];
      mine.push_back(static_cast<std::uint8_t>(j & 0xFF));
      mine.push_back(static_cast<std::uint8_t>(j >> 8));
    });
  }
  const auto all = c_->allgather(mine);
  for (int q = 0; q < ranks_; ++q) {
    if (q == rank_) continue;
    const auto& b = all[static_cast<size_t>(q)];
    std::size_t at = 0;
    for (int k = first; k <= last; ++k) {
      const std::int64_t off = offsets[static_cast<size_t>(k)];
      cells_of(boxes[static_cast<size_t>(k)], q, [&](std::int64_t l) {
        if (at + 2 > b.size()) throw std::runtime_error("abcd: rank " + std::to_string(q) + " sent too few inputs");
        inputs[static_cast<size_t>(off + l)] = static_cast<std::uint16_t>(b[at] | (b[at + 1] << 8));
        at += 2;
      });
    }
    if (at != b.size()) throw std::runtime_error("abcd: rank " + std::to_string(q) + " sent too many inputs");
  }
  return static_cast<std::int64_t>(mine.size());
}

long long SweepSplit::sum(long long mine) const {
  if (!split()) return mine;
  std::vector<std::uint8_t> b(sizeof mine);
  std::memcpy(b.data(), &mine, sizeof mine);
  long long total = 0;
  for (const auto& v : c_->allgather(b)) {
    long long x = 0;
    if (v.size() != sizeof x) throw std::runtime_error("abcd: a rank sent a malformed count");
    std::memcpy(&x, v.data(), sizeof x);
    total += x;
  }
  return total;
}

}  // namespace marsyn::abcd
