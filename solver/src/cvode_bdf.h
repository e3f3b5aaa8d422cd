// The CVODE set-up both references share (reference_integrator.cc for a pair, train_reference.cc
// for a train): BDF with a dense direct solver and the caller's analytic Jacobian, per-slot
// absolute tolerances (positions, velocities, then 1 for the constant and input slots), root
// functions, and every SUNDIALS object owned here (freed in reverse order, also on an exception).
#pragma once

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>
#include <string>

namespace gearnvh {

class CvodeBdf {
 public:
  struct Setup {
    int n = 0;  // reduced DOF: slots [0, n) positions, [n, 2n) velocities
    double rtol = 0.0, atol_position = 0.0, atol_velocity = 0.0;
    CVRhsFn rhs = nullptr;
    CVLsJacFn jacobian = nullptr;
    CVRootFn roots = nullptr;
    int root_count = 0;
    void* user_data = nullptr;
  };

  CvodeBdf(const Eigen::VectorXd& z0, const Setup& setup) {
    SUNContext_Create(nullptr, &ctx_);
    const long m = z0.size();
    y_ = N_VNew_Serial(m, ctx_);
    abstol_ = N_VNew_Serial(m, ctx_);
    for (long i = 0; i < m; ++i) {
      NV_Ith_S(y_, i) = z0[i];
      NV_Ith_S(abstol_, i) =
          i < setup.n ? setup.atol_position : (i < 2 * setup.n ? setup.atol_velocity : 1.0);
    }
    J_ = SUNDenseMatrix(m, m, ctx_);
    solver_ = SUNLinSol_Dense(y_, J_, ctx_);
    mem_ = CVodeCreate(CV_BDF, ctx_);
    CVodeInit(mem_, setup.rhs, 0.0, y_);
    CVodeSVtolerances(mem_, setup.rtol, abstol_);
    CVodeSetUserData(mem_, setup.user_data);
    CVodeSetLinearSolver(mem_, solver_, J_);
    CVodeSetJacFn(mem_, setup.jacobian);
    CVodeSetMaxNumSteps(mem_, 1000000);
    CVodeRootInit(mem_, setup.root_count, setup.roots);
    // Library code never prints: CVODE's messages are kept for the caller's result.
    CVodeSetErrHandlerFn(mem_, KeepMessage, &last_message_);
  }
  ~CvodeBdf() {
    CVodeFree(&mem_);
    SUNLinSolFree(solver_);
    SUNMatDestroy(J_);
    N_VDestroy(abstol_);
    N_VDestroy(y_);
    SUNContext_Free(&ctx_);
  }
  CvodeBdf(const CvodeBdf&) = delete;
  CvodeBdf& operator=(const CvodeBdf&) = delete;

  void* mem() const { return mem_; }
  N_Vector y() const { return y_; }  // the state CVODE advances
  SUNContext context() const { return ctx_; }
  // CVODE's last error or warning message ("" if none).
  const std::string& last_message() const { return last_message_; }
  // Steps since the last (re)initialisation (CVodeReInit resets CVODE's counter).
  long StepsSoFar() const {
    long steps = 0;
    CVodeGetNumSteps(mem_, &steps);
    return steps;
  }

 private:
  static void KeepMessage(int, const char*, const char*, char* message, void* kept) {
    *static_cast<std::string*>(kept) = message;
  }

  std::string last_message_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr, abstol_ = nullptr;
  SUNMatrix J_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
  void* mem_ = nullptr;
};

}  // namespace gearnvh
