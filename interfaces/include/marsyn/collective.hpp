#pragma once
// A group of cooperating processes (ranks) working on one computation, as a tracker sees it:
// how many there are, which one this is, and the two exchanges a split computation needs. Core
// implements it over MPI (docs/mpi.md); plugins see only this header, so they neither depend on
// core nor link MPI. Every member of the group must make the same calls in the same order (the
// usual collective rule): a call on one rank without its partners on the others blocks.
//
// Calls come from one thread per rank (the tracker's calling thread), never from its workers.
#include <cstdint>
#include <vector>

namespace marsyn {

class Collective {
 public:
  virtual ~Collective() = default;
  virtual int rank() const = 0;  // 0 .. size() - 1
  virtual int size() const = 0;
  // Every rank contributes `mine` (any length, lengths may differ); every rank receives all
  // contributions, indexed by rank.
  virtual std::vector<std::vector<std::uint8_t>> allgather(const std::vector<std::uint8_t>& mine) const = 0;
  // Rank `root`'s `bytes` replace every other rank's (any length; the others' input is ignored).
  virtual void broadcast(std::vector<std::uint8_t>& bytes, int root) const = 0;
};

// One process alone: what a tracker gets when nothing is split.
class SerialCollective final : public Collective {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::vector<std::uint8_t>> allgather(const std::vector<std::uint8_t>& mine) const override { return {mine}; }
  void broadcast(std::vector<std::uint8_t>&, int) const override {}
};

// Packs bits, eight to a byte, lowest bit first (the winning sets a split sweep exchanges).
inline std::vector<std::uint8_t> pack_bits(const std::vector<bool>& bits) {
  std::vector<std::uint8_t> out((bits.size() + 7) / 8, 0);
  for (std::size_t i = 0; i < bits.size(); ++i)
    if (bits[i]) out[i / 8] |= static_cast<std::uint8_t>(1u << (i % 8));
  return out;
}
inline bool bit_at(const std::vector<std::uint8_t>& packed, std::size_t i) {
  return i / 8 < packed.size() && ((packed[i / 8] >> (i % 8)) & 1u) != 0;
}

}  // namespace marsyn
