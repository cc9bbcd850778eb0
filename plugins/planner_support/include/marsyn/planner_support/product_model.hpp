#pragma once
// The transcription the nlopt, ipopt and ompl planners share: the product system's RK4 map
// with exact per-agent Jacobians, and the eps-robust requirements of a PlanningProblem as flat
// rows g(x) <= 0 with sparse supports (state bounds and stage constraints at k = 1..T; goal box
// and terminal constraints at k = T). x_0 is fixed, so nothing is required of it: a solver
// cannot change it, and the exact check reports it on its own.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "marsyn/planner.hpp"

namespace marsyn::planner_support {

// Rows of g(x) <= 0 with their sparsity; a bound row reads one coordinate.
class RowSet {
 public:
  void add_lower(int coord, double lo);  // lo - x[coord] <= 0
  void add_upper(int coord, double hi);  // x[coord] - hi <= 0
  void add(const Constraint* c);
  int rows() const { return rows_; }
  int nonzeros() const { return nnz_; }
  // Row and product-state column of each Jacobian entry, in the order evaluate() writes them.
  void pattern(std::vector<int>& row, std::vector<int>& col) const;
  // g (rows()) and, when non-null, the Jacobian entries (nonzeros()) at product state x. With
  // knot >= 0, the rows of constraints that do not apply there (ConstraintStage::AtSteps, a
  // mission stage's visit) read -1 with a zero Jacobian, so every knot keeps the same rows.
  void evaluate(const double* x, double* g, double* jac, int knot = -1) const;
  // Dense Jacobian (rows() x n) from the entries.
  void dense(const double* jac, Eigen::MatrixXd& J) const;
  // The largest g, and the name of the row attaining it.
  double worst(const double* x, std::string* name, int knot = -1) const;
  // Names of the product state's coordinates ("theta of e2"), for the bounds' rows in worst():
  // a user reads agents and states, not product indices.
  void name_coordinates(std::vector<std::string> names) { coord_names_ = std::move(names); }

 private:
  struct Item {
    const Constraint* c = nullptr;
    int coord = -1;
    double sign = 0.0, bound = 0.0;
  };
  std::vector<Item> items_;
  std::vector<std::string> coord_names_;
  int rows_ = 0, nnz_ = 0;
  mutable std::vector<double> scratch_g_, scratch_j_;
};

// A point of the shrunk goal every planner aims at: its centre where bounded, the bound where
// half-bounded, x0's coordinate where free.
Eigen::VectorXd goal_centre(const PlanningProblem& pp);

class ProductModel {
 public:
  explicit ProductModel(const PlanningProblem& pp);

  struct Agent {
    const Dynamics* dyn;
    int xo, uo, n, m;
  };
  const PlanningProblem& pp;
  int n = 0, m = 0, T = 0;
  double tau = 0.1;
  int substeps = 4;
  std::vector<Agent> agents;
  RowSet path, terminal;        // path at k = 1..T (AtSteps rows only at their knots), terminal at k = T (in addition)
  // Between the samples (PlanningProblem::between): these rows at the interior points
  // j = 1..points of every period k = 0..T-1, functions of (x_k, u_k).
  RowSet between;
  int points = 0;
  Eigen::VectorXd goal_centre;  // a point of the shrunk goal (centre where bounded)

  void step(const double* x, const double* u, double* out) const;
  // Block-diagonal product Jacobians, dense: A (n x n), B (n x m).
  void jacobians(const double* x, const double* u, Eigen::MatrixXd& A, Eigen::MatrixXd& B) const;
  std::vector<Eigen::VectorXd> rollout(const std::vector<Eigen::VectorXd>& U) const;
  // The interior point j (1..points) of the period from x under u, and its block-diagonal
  // product Jacobians in x (n x n) and u (n x m).
  void interior(const double* x, const double* u, int j, double* z) const;
  void interior_jacobians(const double* x, const double* u, int j, Eigen::MatrixXd& A, Eigen::MatrixXd& B) const;
  // Largest violation of every requirement (inputs, path, terminal) along a rollout.
  double violation(const std::vector<Eigen::VectorXd>& X, const std::vector<Eigen::VectorXd>& U,
                   std::string* worst) const;
  // Warm start inputs when present and long enough, else zeros clamped into U.
  std::vector<Eigen::VectorXd> initial_inputs() const;
};

}  // namespace marsyn::planner_support
