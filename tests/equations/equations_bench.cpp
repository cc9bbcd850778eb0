// Interpreted equations vs compiled plugins on the tracker's hot path: successor boxes per
// second (abcd::SuccessorBox, FastInterval/DualFI inside) for the unicycle and the cart-pole,
// the equation model and the plugin interleaved in one run. The boxes must be bit-identical.
// Usage: marsyn_equations_bench [seconds per measurement, default 1]
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "equations/equation_dynamics.hpp"
#include "marsyn/stopwatch.hpp"
#include "successor_box.hpp"

using namespace marsyn;

namespace {

struct Work {
  std::vector<std::vector<Interval>> cells;
  std::vector<std::vector<double>> inputs;
};

Work make_work(const std::vector<double>& lo, const std::vector<double>& hi, const std::vector<double>& eta,
               const std::vector<double>& ulo, const std::vector<double>& uhi, int count) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Work w;
  for (int c = 0; c < count; ++c) {
    std::vector<Interval> cell;
    for (std::size_t i = 0; i < lo.size(); ++i) {
      const double a = lo[i] + unit(rng) * (hi[i] - lo[i]);
      cell.emplace_back(a, a + eta[i]);
    }
    std::vector<double> u;
    for (std::size_t j = 0; j < ulo.size(); ++j) u.push_back(ulo[j] + unit(rng) * (uhi[j] - ulo[j]));
    w.cells.push_back(cell);
    w.inputs.push_back(u);
  }
  return w;
}

// Boxes per second over `seconds`; `sum` collects the bounds so that the work is not elided.
double rate(const abcd::SuccessorBox& sb, const Work& w, double seconds, std::vector<double>* boxes) {
  const std::size_t n = w.cells.front().size();
  std::vector<double> lo(n), hi(n);
  long long count = 0;
  const Stopwatch clock;
  double elapsed = 0;
  do {
    for (std::size_t c = 0; c < w.cells.size(); ++c) {
      const bool ok = sb.compute(w.cells[c].data(), w.inputs[c].data(), lo.data(), hi.data());
      if (boxes && count < static_cast<long long>(w.cells.size())) {
        boxes->push_back(ok);
        boxes->insert(boxes->end(), lo.begin(), lo.end());
        boxes->insert(boxes->end(), hi.begin(), hi.end());
      }
      ++count;
    }
    elapsed = clock.seconds();
  } while (elapsed < seconds);
  return static_cast<double>(count) / elapsed;
}

int compare(const char* name, const Dynamics& plugin, const Dynamics& eq, const std::vector<double>& wbound,
            const Work& work, double seconds) {
  abcd::SuccessorOptions opt;
  opt.tau = 0.1;
  const abcd::SuccessorBox a(plugin, wbound, opt), b(eq, wbound, opt);
  std::vector<double> boxes_a, boxes_b;
  double ra = 0, rb = 0;
  for (int round = 0; round < 5; ++round) {  // interleaved; the best of five each (shared machines)
    ra = std::max(ra, rate(a, work, seconds, round == 0 ? &boxes_a : nullptr));
    rb = std::max(rb, rate(b, work, seconds, round == 0 ? &boxes_b : nullptr));
  }
  const bool same = boxes_a == boxes_b;
  std::printf("%-9s plugin %9.0f boxes/s   equations %9.0f boxes/s   time equations / plugin %.2f   boxes %s\n",
              name, ra, rb, ra / rb, same ? "bit-identical" : "DIFFER");
  return same ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  equations::EquationSpec uni;
  uni.states = {"x", "y", "theta"};
  uni.inputs = {"v", "omega"};
  uni.field = {{"x", "v * cos(theta)"}, {"y", "v * sin(theta)"}, {"theta", "omega"}};
  const equations::EquationDynamics uni_eq(uni);
  const models::Unicycle uni_plugin;
  int bad = compare("unicycle", uni_plugin, uni_eq, {0, 0.025, 0.025},
                    make_work({-1, -1, -2}, {11, 11, 3.3}, {0.025, 0.025, 0.03}, {-2.4, -2.4}, {2.4, 2.4}, 2000), seconds);

  equations::EquationSpec cp;
  cp.states = {"z", "z_dot", "theta", "theta_dot"};
  cp.inputs = {"force"};
  cp.constants = {{"gravity", 9.8}, {"cart_mass", 1.0}, {"pole_mass", 0.1}, {"half_pole_length", 0.5}};
  cp.definitions = {
      {"push", "(force + pole_mass * half_pole_length * (theta_dot * theta_dot) * sin(theta)) / (cart_mass + pole_mass)"},
      {"th_dd", "(gravity * sin(theta) - cos(theta) * push) / (half_pole_length * (4.0 / 3.0 - (pole_mass / "
                "(cart_mass + pole_mass)) * (cos(theta) * cos(theta))))"}};
  cp.field = {{"z", "z_dot"},
              {"z_dot", "push - (pole_mass * half_pole_length / (cart_mass + pole_mass)) * th_dd * cos(theta)"},
              {"theta", "theta_dot"},
              {"theta_dot", "th_dd"}};
  const equations::EquationDynamics cp_eq(cp);
  const models::CartPole cp_plugin;
  bad += compare("cartpole", cp_plugin, cp_eq, {0, 0.01, 0, 0.01},
                 make_work({-1, -1, 2.5, -1}, {1, 1, 3.8, 1}, {0.02, 0.02, 0.02, 0.02}, {-5}, {5}, 2000), seconds);
  return bad;
}
