#pragma once

#include <mpi.h>

/// @file
/// The mechanics' own matrix-free tangent (Problem::matrix_free_tangent())
/// against the Problem's assembled sparse tangent, on a Land problem 2-like
/// ventricle: the unit and the MPI test share it.

namespace test_support
{
  /// Relative differences max_i |(K x)_i - (K_mf x)_i| / max_i |(K x)_i|
  /// (over all ranks and three random x, zero on the constrained DoFs).
  struct MatrixFreeProblemDifferences
  {
    /// The general cached tangent at the assembly's tension.
    double cached = 0;
    /// The same in single precision (Variant::cached_single).
    double single = 0;
    /// The cached tangent at another tension (the uniform tension 0 instead
    /// of 10 kPa): what the check would see if the active stress were lost.
    double other_tension = 0;
    /// The cached tangent after the displacement changed (update_matrix_
    /// free_tangent() brings it back: cached again), before the update.
    double stale = 0;
    /// After ProblemChecks::update_matrix_free_tangent() at the new
    /// displacement.
    double updated = 0;
    /// With the follower pressure of 10 kPa on the endocardium (its face
    /// term) against the assembled tangent under that pressure.
    double pressure = 0;
    /// The bulk term alone against the assembled tangent under pressure:
    /// what the check would see if the face term were lost.
    double pressure_left_out = 0;
  };

  /// The Land ventricle (Geometry::Parameters' default, Q2 on MappingQ2) of
  /// the Guccione law of the tests with rule-based fibres, the Simo-Taylor
  /// penalty, base fixed, no cavity pressure (the assembled tangent is the
  /// bulk term alone; then 10 kPa on the endocardium), a uniform active tension
  /// of 10 kPa plus a per-point one varying in space, at the displacement
  /// Wobble; on @p comm.
  MatrixFreeProblemDifferences
  matrix_free_problem_differences(const MPI_Comm comm);
} // namespace test_support
