#pragma once

#include <deal.II/lac/generic_linear_algebra.h>

/// The one place that names the linear-algebra backend.
namespace systole
{
  namespace LA = dealii::LinearAlgebraPETSc;
}
