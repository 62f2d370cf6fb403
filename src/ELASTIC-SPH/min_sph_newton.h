/* -*- c++ -*- ----------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

#ifdef MINIMIZE_CLASS
// clang-format off
MinimizeStyle(sph/newton,MinSPHNewton);
// clang-format on
#else

#ifndef LMP_MIN_SPH_NEWTON_H
#define LMP_MIN_SPH_NEWTON_H

#include "min_linesearch.h"

#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

namespace SPHElastic {
  class FreeHessian;
  class HessianOperators;
  class ICBLinearisation;
  class LinearSolver;
  class LinearSolverChoice;
  class NewtonDofs;
}    // namespace SPHElastic

/* ----------------------------------------------------------------------
   Newton's method for pair_style sph/icb.  With stress pk1 each iteration
   solves H step = f on the free coordinates (SPHElastic::NewtonDofs finds
   them by probing the fixes; SPHElastic::FreeHessian gives H; a
   SPHElastic::LinearSolver assembles and solves it) and shortens the step
   by backtracking on the energy.  The corotated stress has no energy and
   an unsymmetric Jacobian J: Newton-Krylov solves J step = f by flexible
   GMRES on finite-difference products J v, preconditioned by the pk1
   Hessian H (the same elastic law and, to first order in the strain, the
   same Jacobian), and backtracks on |f|^2.  With hourglass control the
   pk1 step is solved by the same GMRES on exact Hessian products.
------------------------------------------------------------------------- */

class MinSPHNewton : public MinLineSearch {
 public:
  MinSPHNewton(class LAMMPS *);
  ~MinSPHNewton() override;
  void init() override;
  int iterate(int) override;
  int modify_param(int, char **) override;

 private:
  // the line searches: sufficient-decrease fraction (Armijo) and halvings
  // before they give up
  static constexpr double ARMIJO = 1.0e-4;
  static constexpr int MAXHALVING = 40;
  // the forcing term eta of an inexact Newton step (|H s - f| <= eta |f|):
  // Eisenstat and Walker's choice 2 within [ETA_MIN, ETA_MAX]
  static constexpr double ETA_MAX = 1.0e-2;
  static constexpr double ETA_MIN = 1.0e-8;
  class PairSPHICB *pair;
  std::unique_ptr<SPHElastic::NewtonDofs> dofs;
  std::unique_ptr<SPHElastic::ICBLinearisation> linearisation;
  std::unique_ptr<SPHElastic::FreeHessian> hessian;
  std::unique_ptr<SPHElastic::LinearSolverChoice> choice;
  std::unique_ptr<SPHElastic::LinearSolver> solver;
  std::unique_ptr<SPHElastic::HessianOperators> operators;
  std::vector<double> force_rows, step;    // this rank's rows of them on the free coordinates
  int terms_vector;                        // fix MINIMIZE's vector of the per-atom terms
  int nroundoff;                           // line searches in a row that ended below round-off
  double roundoff_fnorm;                   // |f|^2 when that run began
  // Newton-Krylov (stress corotated)
  std::vector<double> residual;     // the free force at the iterate, this rank's rows
  std::vector<double> perturbed;    // the same at iterate + eps v
  double fd_length;                 // largest coordinate change of a difference product
  bigint nkrylov, nproducts;        // GMRES iterations on J v and its force calls, this run

  void setup_style() override;
  void check_style();
  void start();
  int newton_loop(int);
  void newton_step(double tol);
  bool saddle_point();
  int line_search(double fdoth);
  int abandon_step(bool all_inverted, const std::string &reason);
  bool trial_inverts() const;
  int corotated_loop(int);
  int newton_krylov_loop(int);
  int residual_line_search(double phi0, double eta);
  void jacobian_product(const std::vector<double> &v, std::vector<double> &jv);
  static double forcing_term(double previous_eta, double fsq, double fsq_previous);
  void pk1_inverse(const std::vector<double> &v, std::vector<double> &z);
  void free_force(std::vector<double> &force);
  bool force_below_ftol();
  int stop_or_output(bigint ntimestep, bool test_energy);
};

}    // namespace LAMMPS_NS

#endif
#endif
