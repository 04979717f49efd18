#pragma once

#include <deal.II/base/mpi.h>

#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace systole
{
  class Logger;
  struct RunParameters;

  /// Run the "mechanics" problem: build the mesh, ramp the pressure and the
  /// active tension from zero to their full values in load steps (halving a
  /// step whose Newton solve fails), and write one time-series row per
  /// converged step (load fraction, loads, Newton iterations, cavity volume,
  /// tracked points) and the displacement field.
  void
  run_quasi_static_problem(const dealii::ParameterHandler &prm,
                           const RunParameters            &run,
                           const std::string              &parameter_text,
                           Logger                         &logger,
                           const MPI_Comm                  comm);
} // namespace systole
