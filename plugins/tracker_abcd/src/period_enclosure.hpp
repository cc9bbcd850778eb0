#pragma once
// The continuous-time half of the tracker's guarantee: where the closed loop can be between two
// samples. For every step k, every winning cell of step k and its stored input, the a priori
// enclosures of the successor computation (successor_box.hpp) bound every state over each part
// of the period; the hull over a step's winning cells, part by part, is what a certifier checks
// against the specification (docs/soundness.md, "Continuous time").
#include <string>
#include <vector>

#include "controller_file.hpp"
#include "marsyn/collective.hpp"
#include "marsyn/tracker.hpp"
#include "successor_box.hpp"

namespace marsyn::abcd {

struct EnclosureOptions {
  int substeps = 8;  // parts of each period, each with its own box
  // Cells sharing an input are enclosed together in blocks of `block` cells along each
  // coordinate the field reads: fewer computations, boxes a few cells wider.
  int block = 4;
  int threads = 1;
  // Ranks sharing the work (split_sweep.hpp): steps are dealt round-robin and every rank ends
  // with every step's boxes. nullptr: this process alone.
  const Collective* collective = nullptr;
};

// Fills d.enclosures for steps 0..T-1 of a tracking controller. Cells that differ only along
// coordinates the field does not read (`invariant`, already restricted to indices where
// SuccessorTable::shift_valid holds) share one enclosure of a canonical cell centred at 0 along
// them, shifted by the cells' exact centres: translating the state along those coordinates
// translates every solution, so one computation per (other indices, input) serves every row and
// every step. Along the other coordinates, cells with the same input are enclosed per block of
// o.block cells (the whole block, aligned in absolute indices, so the entry serves every step).
// Returns false (with `why`) when some winning cell has no enclosure.
bool compute_period_enclosures(const TrackingProblem& p, const std::vector<bool>& invariant, const SuccessorBox& sb,
                               const EnclosureOptions& o, ControllerData& d, std::string& why);

}  // namespace marsyn::abcd
