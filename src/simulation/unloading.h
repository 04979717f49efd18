#pragma once

#include "simulation/problem_type.h"
#include "simulation/unloading_parameters.h"

#include <string>

namespace systole
{
  /// Run the "unloading" problem: take the mesh of the parameter file as the
  /// geometry x_img of the ventricle imaged at the cavity pressure
  /// Unloading / Image pressure, and find the stress-free reference X whose
  /// inflation to that pressure gives x_img, by the backward-displacement
  /// fixed point (Sellier 2011; Bols et al. 2013, J. Comput. Appl. Math.
  /// 255:505): X_{k+1} = X_k + omega_k (x_img - X_k - u(X_k)), u(X_k) the
  /// displacement of a load-stepped forward solve on the reference X_k,
  /// omega_k = 1 (plain) or Aitken's dynamic relaxation. The reference is the
  /// mesh's vertices, moved on every rank (curved manifolds are dropped
  /// first); the fibres are recomputed on every reference. Writes the
  /// unloaded mesh (gmsh), one time-series row per iteration, a /summary row
  /// and the unloading displacement x_img - X as a field.
  void
  run_unloading_problem(const RunInputs &in);
} // namespace systole
