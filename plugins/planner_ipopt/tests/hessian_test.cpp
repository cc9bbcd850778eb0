// Second derivatives of the multiple-shooting Lagrangian: AD blocks against differences of the
// exact AD gradients, the assembled sparse Hessian against differences of the assembled
// gradient, and Ipopt's own second-order derivative checker.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "ipopt_solver.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/sampled_map.hpp"
#include "second_order.hpp"
#include "shooting_nlp.hpp"
#include "test_problems.hpp"

using namespace marsyn;
using ipopt_planner::SecondOrderField;

namespace {

// The interfaces cannot evaluate a model with DualD2 yet (second_order.hpp); the tests hold the
// concrete models and hand their templates to the planner, as an interface overload would.
template <class Model>
SecondOrderField field_of(const Model& model) {
  return [&model](const DualD2* x, const DualD2* u, DualD2* dx) { model.vector_field(x, u, dx); };
}

using Gradient = std::function<void(const std::vector<double>& z, std::vector<double>& g)>;

// Reference Hessian (row r, column j: d g_r / d z_j) from an exact gradient: Richardson
// extrapolation of central differences at steps h and h/2, error O(h^4). `tolerance` bounds that
// error: the distance between the extrapolation and the plain difference at h/2 (its O(h^2)
// truncation error, far above the extrapolation's own), plus the rounding of differencing
// gradients of size |g| at step h/2.
struct Reference {
  std::vector<double> H;
  double tolerance = 0.0;
};

Reference differenced(const Gradient& grad, std::vector<double> z, double rel_step) {
  const int w = static_cast<int>(z.size());
  Reference ref;
  ref.H.assign(static_cast<size_t>(w) * w, 0.0);
  std::vector<double> gp(w), gm(w);
  double truncation = 0.0, gmax = 0.0, hmin = INFINITY;
  auto central = [&](int j, double h, std::vector<double>& col) {
    const double zj = z[j];
    z[j] = zj + h;
    grad(z, gp);
    z[j] = zj - h;
    grad(z, gm);
    z[j] = zj;
    col.resize(w);
    for (int r = 0; r < w; ++r) {
      col[r] = (gp[r] - gm[r]) / (2 * h);
      gmax = std::max({gmax, std::abs(gp[r]), std::abs(gm[r])});
    }
  };
  std::vector<double> d1, d2;
  for (int j = 0; j < w; ++j) {
    const double h = rel_step * std::max(1.0, std::abs(z[j]));
    hmin = std::min(hmin, h);
    central(j, h, d1);
    central(j, 0.5 * h, d2);
    for (int r = 0; r < w; ++r) {
      const double R = (4.0 * d2[r] - d1[r]) / 3.0;
      ref.H[r * w + j] = R;
      truncation = std::max(truncation, std::abs(d2[r] - R));
    }
  }
  ref.tolerance = truncation + 64 * std::numeric_limits<double>::epsilon() * std::max(1.0, gmax) / (0.5 * hmin);
  return ref;
}

double mismatch(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

// A block passes against its reference, and fails once any single entry is off by a few times
// the tolerance (the comparison is sharp enough to see one wrong entry).
void expect_matches(const std::vector<double>& H, const Reference& ref, const std::string& what) {
  double scale = 1.0;
  for (double v : H) scale = std::max(scale, std::abs(v));
  EXPECT_LE(mismatch(H, ref.H), ref.tolerance) << what << ": tolerance " << ref.tolerance << ", scale " << scale;
  EXPECT_LT(ref.tolerance, 1e-6 * scale) << what << ": the reference is too coarse to test anything";
  for (size_t i = 0; i < H.size(); ++i) {
    auto bad = H;
    bad[i] += 3 * ref.tolerance + 1e-12 * scale;
    ASSERT_GT(mismatch(bad, ref.H), ref.tolerance) << what << ": a perturbed entry " << i << " passes";
  }
}

// One agent's dynamics block: AD Hessian of lam' f_tau against differences of the exact AD
// gradient lam' [A B] (marsyn::rk4_jacobians through the Dynamics interface), at random points.
template <class Model>
void check_dynamics_blocks(const Model& model, double tau, int substeps, unsigned seed, const std::string& name) {
  const int n = model.state_dim(), m = model.input_dim(), w = n + m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-2.0, 2.0);
  const auto field = field_of(model);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> z(w), lam(n), H(static_cast<size_t>(w) * w);
    for (auto& v : z) v = U(rng);
    for (auto& v : lam) v = U(rng);
    ipopt_planner::rk4_weighted_hessian(field, n, m, z.data(), z.data() + n, lam.data(), tau, substeps, H.data());
    const Gradient grad = [&](const std::vector<double>& p, std::vector<double>& g) {
      std::vector<double> A(n * n), B(n * m);
      rk4_jacobians(model, p.data(), p.data() + n, tau, substeps, nullptr, A.data(), B.data());
      for (int j = 0; j < w; ++j) {
        g[j] = 0.0;
        for (int r = 0; r < n; ++r) g[j] += lam[r] * (j < n ? A[r * n + j] : B[r * m + j - n]);
      }
    };
    expect_matches(H, differenced(grad, z, 1e-3), name + " trial " + std::to_string(trial));
    // The differenced block the `differenced` mode uses agrees to its O(h^2) (h = 1e-5).
    std::vector<double> Hd(H.size());
    ipopt_planner::differenced_dynamics_hessian(model, z.data(), z.data() + n, lam.data(), tau, substeps, 0,
                                                Hd.data());
    EXPECT_LE(mismatch(H, Hd), 1e-6) << name;
  }
}

}  // namespace

TEST(IpoptHessian, NestedDualsGiveExactSecondDerivativesOfEveryElementaryFunction) {
  // f(a, b) = sin(a) cos(b) + exp(a b) + sqrt(a^2 + b) + tan(a - b) + atan(a / b), differentiated
  // twice by DualD2 and by hand.
  const double a = 0.7, b = 1.3;
  const DualD2 A = second_order_variable(a, 0, 2), B = second_order_variable(b, 1, 2);
  const DualD2 f = sin(A) * cos(B) + exp(A * B) + sqrt(A * A + B) + tan(A - B) + atan(A / B);
  const double s = std::sqrt(a * a + b), t = std::tan(a - b), e = std::exp(a * b);
  const double sec2 = 1 + t * t, q = a / b, den = 1 + q * q;
  // d2/da2, d2/dadb, d2/db2 of each term.
  const double faa = -std::sin(a) * std::cos(b) + b * b * e + (1 / s - a * a / (s * s * s)) + 2 * t * sec2 +
                     (-2 * q / (den * den)) / (b * b);
  const double fab = -std::cos(a) * std::sin(b) + (1 + a * b) * e - a / (2 * s * s * s) - 2 * t * sec2 +
                     (-1 / (b * b * den) + 2 * q * q / (b * b * den * den));
  const double fbb = -std::sin(a) * std::cos(b) + a * a * e - 1 / (4 * s * s * s) + 2 * t * sec2 +
                     (2 * q / (b * b * den) - 2 * q * q * q / (b * b * den * den));
  EXPECT_NEAR(second_derivative(f, 0, 0), faa, 1e-12 * std::abs(faa) + 1e-13);
  EXPECT_NEAR(second_derivative(f, 0, 1), fab, 1e-12 * std::abs(fab) + 1e-13);
  EXPECT_NEAR(second_derivative(f, 1, 0), fab, 1e-12 * std::abs(fab) + 1e-13);
  EXPECT_NEAR(second_derivative(f, 1, 1), fbb, 1e-12 * std::abs(fbb) + 1e-13);
  // The first layer is the DualD gradient, the value the double one.
  const DualD Ad = DualD::variable(a, 0, 2), Bd = DualD::variable(b, 1, 2);
  const DualD fd = sin(Ad) * cos(Bd) + exp(Ad * Bd) + sqrt(Ad * Ad + Bd) + tan(Ad - Bd) + atan(Ad / Bd);
  EXPECT_EQ(f.v.v, fd.v);
  EXPECT_EQ(f.v.derivative(1), fd.derivative(1));
  EXPECT_EQ(f.derivative(0).v, fd.derivative(0));
}

TEST(IpoptHessian, DynamicsBlocksOfEveryModelMatchDifferencedExactGradients) {
  check_dynamics_blocks(models::Pendulum(), 0.1, 4, 1, "pendulum");
  check_dynamics_blocks(models::Unicycle(), 0.1, 4, 2, "unicycle");
  check_dynamics_blocks(models::CartPole(), 0.1, 4, 3, "cartpole");
  check_dynamics_blocks(models::DoubleIntegrator(), 0.1, 4, 4, "double integrator");
  check_dynamics_blocks(models::CartPole(), 0.25, 1, 5, "cartpole, one substep");
}

TEST(IpoptHessian, TheInterfaceHooksAreDetected) {
  // What switches the exact blocks on without an edit in the plugin (second_order.hpp).
  struct FieldWithNestedDuals {
    void field(const DualD2*, const DualD2*, DualD2*) const {}
  };
  struct ConstraintWithHessian {
    bool hessian(const double*, const double*, double* H) const {
      H[0] += 2.0;
      return true;
    }
  };
  static_assert(ipopt_planner::HasSecondOrderField<FieldWithNestedDuals>);
  static_assert(ipopt_planner::HasConstraintHessian<ConstraintWithHessian>);
  EXPECT_TRUE(static_cast<bool>(ipopt_planner::second_order_field(FieldWithNestedDuals{})));
  double x = 0.0, H = 1.0;
  EXPECT_TRUE(ipopt_planner::constraint_hessian(ConstraintWithHessian{}, &x, &x, &H));
  EXPECT_EQ(H, 3.0);
  std::cout << "marsyn::Dynamics DualD2 field: " << ipopt_planner::interface_has_second_order_field()
            << ", marsyn::Constraint::hessian: " << ipopt_planner::interface_has_constraint_hessian() << "\n";
}

TEST(IpoptHessian, AssembledLagrangianHessianMatchesDifferencedLagrangianGradient) {
  // Two unicycles, pair and obstacle rows, a short horizon: every kind of block, and the
  // lower-triangle scatter with summed duplicates, against differences of sigma grad f + J' lambda.
  const auto p = testproblems::unicycle_crossing(5, true);
  const auto pp = planning::assemble(p, p.horizon);
  planner_support::ProductModel model(pp);
  ipopt_planner::Options o;
  PlanOptions run;
  const models::Unicycle uni;
  Ipopt::SmartPtr<ipopt_planner::ShootingNlp> nlp =
      new ipopt_planner::ShootingNlp(model, o, run, Stopwatch(), {field_of(uni), field_of(uni)});
  Ipopt::Index nv, nc, nj, nh;
  Ipopt::TNLP::IndexStyleEnum style;
  nlp->get_nlp_info(nv, nc, nj, nh, style);
  std::vector<Ipopt::Index> hr(nh), hc(nh), jr(nj), jc(nj);
  nlp->eval_h(nv, nullptr, true, 1.0, nc, nullptr, true, nh, hr.data(), hc.data(), nullptr);
  nlp->eval_jac_g(nv, nullptr, true, nc, nj, jr.data(), jc.data(), nullptr);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<double> z(nv), lambda(nc);
  for (int k = 1; k <= model.T; ++k)
    for (int i = 0; i < model.n; ++i) z[(k - 1) * model.n + i] = pp.x0[i] + 6.0 * k / model.T * (i % 3 == 0) + U(rng);
  for (int i = model.T * model.n; i < nv; ++i) z[i] = 2.0 * U(rng);
  for (auto& l : lambda) l = U(rng);
  const double sigma = 0.7;

  std::vector<double> hv(nh);
  nlp->eval_h(nv, z.data(), true, sigma, nc, lambda.data(), true, nh, nullptr, nullptr, hv.data());
  EXPECT_EQ(nlp->hessian_blocks().dynamics_exact, model.T * 2);
  EXPECT_EQ(nlp->hessian_blocks().dynamics_differenced, 0);
  auto dense = [&](const std::vector<double>& vals) {
    std::vector<double> H(static_cast<size_t>(nv) * nv, 0.0);
    for (int e = 0; e < nh; ++e) {
      EXPECT_GE(hr[e], hc[e]) << "not in the lower triangle";
      H[hr[e] * nv + hc[e]] += vals[e];
      if (hr[e] != hc[e]) H[hc[e] * nv + hr[e]] += vals[e];
    }
    return H;
  };
  const std::vector<double> H = dense(hv);
  const Gradient grad = [&](const std::vector<double>& zz, std::vector<double>& g) {
    std::vector<double> jv(nj);
    nlp->eval_grad_f(nv, zz.data(), true, g.data());
    for (auto& v : g) v *= sigma;
    nlp->eval_jac_g(nv, zz.data(), true, nc, nj, nullptr, nullptr, jv.data());
    for (int e = 0; e < nj; ++e) g[jc[e]] += lambda[jr[e]] * jv[e];
  };
  const Reference ref = differenced(grad, z, 1e-4);
  double scale = 1.0;
  for (double v : H) scale = std::max(scale, std::abs(v));
  EXPECT_LE(mismatch(H, ref.H), ref.tolerance) << "tolerance " << ref.tolerance << ", scale " << scale;
  EXPECT_LT(ref.tolerance, 1e-6 * scale);
  std::cout << "assembled Hessian: mismatch " << mismatch(H, ref.H) << ", tolerance " << ref.tolerance << ", scale "
            << scale << "\n";
  // One wrong entry of the sparse values is seen.
  for (int e : {0, nh / 3, nh / 2, nh - 1}) {
    auto bad = hv;
    bad[e] += 3 * ref.tolerance + 1e-12 * scale;
    EXPECT_GT(mismatch(dense(bad), ref.H), ref.tolerance) << "perturbed entry " << e;
  }
}

namespace {
std::string derivative_check_log(const std::vector<SecondOrderField>& fields, const std::string& file) {
  ipopt_planner::Options o;
  o.derivative_test = "second-order";
  o.max_iterations = 1;
  o.output_file = file;
  const auto p = testproblems::unicycle_crossing(8, true);
  const auto pp = planning::assemble(p, p.horizon);
  ipopt_planner::solve(pp, {}, o, fields);
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::remove(file.c_str());
  return ss.str();
}
}  // namespace

TEST(IpoptHessian, IpoptsSecondOrderDerivativeCheckerFindsNoErrors) {
  const models::Unicycle uni;
  const std::string exact = derivative_check_log({field_of(uni), field_of(uni)}, "ipopt_derivative_check_exact.log");
  ASSERT_NE(exact.find("Starting derivative checker for second derivatives."), std::string::npos) << exact;
  EXPECT_NE(exact.find("No errors detected by derivative checker."), std::string::npos) << exact;
  // With what the interfaces give today (differenced blocks where they lack second derivatives).
  const std::string plain = derivative_check_log({}, "ipopt_derivative_check_plain.log");
  ASSERT_NE(plain.find("Starting derivative checker for second derivatives."), std::string::npos) << plain;
  EXPECT_NE(plain.find("No errors detected by derivative checker."), std::string::npos) << plain;
}

TEST(IpoptHessian, ExactDynamicsBlocksSolveThePendulum) {
  const auto p = testproblems::pendulum_problem();
  const auto pp = planning::assemble(p, p.horizon);
  const models::Pendulum pend;
  ipopt_planner::Options o;
  const auto exact = ipopt_planner::solve(pp, {}, o, {field_of(pend)});
  o.hessian = "differenced";
  const auto diff = ipopt_planner::solve(pp, {}, o);
  std::cout << "pendulum: exact " << exact.iterations << " iterations (" << exact.solve_time_s << " s, " << exact.message
            << "), differenced " << diff.iterations << " (" << diff.solve_time_s << " s)\n";
  EXPECT_EQ(exact.status, PlannerStatus::ExactSolution) << exact.message;
  EXPECT_EQ(exact.message.find("differenced"), std::string::npos) << exact.message;
  EXPECT_EQ(diff.status, PlannerStatus::ExactSolution) << diff.message;
}
