#pragma once
// Two unicycles driving side by side along x, 1.0 apart in y, above a wall whose top is 0.9 below
// the first, with controllers that are only their period enclosures (the stretch each covers,
// 0.05 wide on each side): the certifier's input, built by hand, for the tests of bodies and
// clearances (body_radius_test.cpp, agent_bodies_test.cpp).
#include <memory>
#include <string>
#include <vector>

#include "marsyn/core/verification/certification.hpp"
#include "../../plugins/dynamics_unicycle/src/unicycle.hpp"

namespace marsyn::test {

inline constexpr int kSideBySideSteps = 6;

class EnclosureController : public Controller {
 public:
  explicit EnclosureController(double y) {
    for (int k = 0; k < kSideBySideSteps; ++k) {
      PeriodEnclosure q;
      q.step = k;
      q.t0 = 0.1 * k;
      q.t1 = 0.1 * (k + 1);
      q.state = {Eigen::Vector3d(0.5 * k - 0.05, y - 0.05, -0.05), Eigen::Vector3d(0.5 * (k + 1) + 0.05, y + 0.05, 0.05)};
      q.workspace = {Eigen::Vector2d(0.5 * k - 0.05, y - 0.05), Eigen::Vector2d(0.5 * (k + 1) + 0.05, y + 0.05)};
      e_.push_back(q);
    }
  }
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  int horizon() const override { return kSideBySideSteps; }
  ControlStatus input(const double*, int, double*) const override { return ControlStatus::OutsideDomain; }
  void write(const std::string&) const override {}
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return e_; }

 private:
  std::vector<PeriodEnclosure> e_;
};

// Agents a (y = 0) and b (y = 1) and the wall [-5, 10] x [-1, -0.9].
inline Problem side_by_side(double delta, double obstacle_delta) {
  Problem pb;
  pb.tau = 0.1;
  pb.horizon = kSideBySideSteps;
  pb.delta = delta;
  pb.delta_obstacles = obstacle_delta;
  Obstacle wall;
  wall.name = "wall";
  wall.is_box = true;
  wall.vertices = {{-5, -1.0}, {10, -1.0}, {10, -0.9}, {-5, -0.9}};
  pb.obstacles.push_back(wall);
  for (int i = 0; i < 2; ++i) {
    AgentSpec a;
    a.name = i ? "b" : "a";
    a.dynamics = std::make_shared<models::Unicycle>();
    a.x0 = Eigen::Vector3d(0, i, 0);
    a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
    a.goal = {Eigen::Vector3d(2.5, i - 0.5, -1), Eigen::Vector3d(3.5, i + 0.5, 1)};
    a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
    pb.agents.push_back(a);
  }
  return pb;
}

inline CertificationReport certify_side_by_side(const Problem& pb) {
  return certify(pb, {std::make_shared<EnclosureController>(0.0), std::make_shared<EnclosureController>(1.0)});
}

}  // namespace marsyn::test
