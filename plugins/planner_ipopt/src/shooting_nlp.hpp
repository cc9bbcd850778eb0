#pragma once
// The multiple-shooting NLP as an Ipopt TNLP (layout in ipopt_solver.hpp).
#include <IpTNLP.hpp>
#include <string>
#include <vector>

#include "ipopt_solver.hpp"
#include "marsyn/planner_support/product_model.hpp"
#include "marsyn/stopwatch.hpp"
#include "second_order.hpp"

namespace marsyn::ipopt_planner {

class ShootingNlp : public Ipopt::TNLP {
 public:
  using Index = Ipopt::Index;
  using Number = Ipopt::Number;

  // `fields`: one per agent, the vector field with nested duals for exact dynamics blocks; empty
  // (or an empty entry) takes what marsyn::Dynamics offers (second_order.hpp).
  ShootingNlp(const planner_support::ProductModel& model, const Options& options, const PlanOptions& run, Stopwatch clock,
              std::vector<SecondOrderField> fields = {});

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override;
  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override;
  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_L, Number* z_U, Index m,
                          bool init_lambda, Number* lambda) override;
  bool eval_f(Index n, const Number* x, bool new_x, Number& obj_value) override;
  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad_f) override;
  bool eval_g(Index n, const Number* x, bool new_x, Index m, Number* g) override;
  bool eval_jac_g(Index n, const Number* x, bool new_x, Index m, Index nele_jac, Index* iRow, Index* jCol,
                  Number* values) override;
  bool eval_h(Index n, const Number* x, bool new_x, Number obj_factor, Index m, const Number* lambda,
              bool new_lambda, Index nele_hess, Index* iRow, Index* jCol, Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number* z_L,
                         const Number* z_U, Index m, const Number* g, const Number* lambda, Number obj_value,
                         const Ipopt::IpoptData* ip_data, Ipopt::IpoptCalculatedQuantities* ip_cq) override;
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Index iter, Number obj_value, Number inf_pr,
                             Number inf_du, Number mu, Number d_norm, Number regularization_size,
                             Number alpha_du, Number alpha_pr, Index ls_trials, const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override;

  // The solution's inputs (u_0..u_{T-1}); empty before finalize_solution.
  const std::vector<Eigen::VectorXd>& inputs() const { return solution_u_; }
  Ipopt::SolverReturn status() const { return status_; }
  bool timed_out() const { return timed_out_; }
  int iterations() const { return iterations_; }
  // How the blocks of the last eval_h were computed (AD second derivatives or differences).
  struct HessianBlocks {
    long dynamics_exact = 0, dynamics_differenced = 0, constraints_exact = 0, constraints_differenced = 0;
    long between = 0;  // blocks of the rows between the samples (exact or differenced as above)
  };
  int hessian_evaluations() const { return h_evals_; }
  double hessian_seconds() const { return h_seconds_; }
  const HessianBlocks& hessian_blocks() const { return blocks_; }

 private:
  int xvar(int k, int i) const { return (k - 1) * n_ + i; }  // k >= 1
  int uvar(int k, int j) const { return T_ * n_ + k * m_ + j; }
  const double* state(const Number* z, int k) const { return k == 0 ? model_.pp.x0.data() : z + xvar(k, 0); }
  // Values and agent Jacobians of f_tau at every step, for the current z.
  void linearize(const Number* z);
  void build_patterns();
  // Rows between the samples (shooting_between.cpp), after the terminal rows.
  struct Between {
    const Constraint* c;
    int offset;               // within one interior point's block of rows
    std::vector<int> agents;  // the agents its support reads
  };
  void setup_between();
  std::vector<int> between_vars(const Between& b, int k) const;
  int between_row(int k, int j, const Between& b) const;  // the row of b's first row at (k, j)
  void between_patterns();
  void interior_at(const Number* z, int k, int j, bool jacobians);
  Eigen::MatrixXd between_jz(const Between& b, int k) const;
  void between_g(const Number* z, Number* g);
  size_t between_jacobian(const Number* z, Number* v);
  size_t between_hessian(const Number* z, const Number* lambda, bool exact, Number* v);
  std::vector<Between> between_;
  int between_rows_ = 0, points_ = 0;
  std::vector<double> point_;                  // an interior point of the product state
  std::vector<std::vector<double>> zA_, zB_;   // its per-agent Jacobians (row-major)

  const planner_support::ProductModel& model_;
  const Options& o_;
  const PlanOptions& run_;
  const Stopwatch clock_;  // started with the solve: the time limit counts from there
  const int T_, n_, m_;
  std::vector<const Constraint*> path_, terminal_;
  int path_rows_ = 0, terminal_rows_ = 0;
  std::vector<Index> jrow_, jcol_, hrow_, hcol_;
  // Cache for the current z: next states and row-major agent Jacobians [A | B] per step.
  std::vector<double> z_cache_;
  std::vector<Eigen::VectorXd> next_;
  std::vector<std::vector<double>> jac_;  // [k * agents + i]: n_i x (n_i + m_i)
  std::vector<SecondOrderField> fields_;
  std::vector<double> hess_;  // one block of eval_h
  HessianBlocks blocks_;
  int h_evals_ = 0;
  double h_seconds_ = 0.0;
  std::vector<Eigen::VectorXd> solution_u_;
  Ipopt::SolverReturn status_ = Ipopt::INTERNAL_ERROR;
  bool timed_out_ = false;
  int iterations_ = 0;
};

}  // namespace marsyn::ipopt_planner
