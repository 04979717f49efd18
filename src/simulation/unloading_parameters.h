#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace systole
{
  /// Subsection "Unloading" of the parameter file (Problem = unloading).
  struct UnloadingParameters
  {
    enum class Acceleration
    {
      none,
      aitken
    };

    double       image_pressure  = 1.333224; ///< [kPa] (10 mmHg)
    double       tolerance       = 0.01;     ///< [mm]
    unsigned int max_iterations  = 30;       ///< fixed-point updates
    Acceleration acceleration    = Acceleration::aitken;
    bool         synthetic_image = false;
    std::string  mesh_file       = "unloaded.msh"; ///< in the run folder

    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads and validates the subsection (clear errors naming the entry).
    static UnloadingParameters
    parse(const dealii::ParameterHandler &prm);
  };
} // namespace systole
