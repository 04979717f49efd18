# Precompiled headers: the deal.II headers most translation units include, parsed once per
# target instead of once per file. The cold build's time and what this saves are measured in
# docs/verification.md ("Build and test time"). Two precompiled headers of this set: the
# library's (position-independent) and the test support's (with Catch2), which the unit and MPI
# test executables reuse (tests/CMakeLists.txt).
set(SYSTOLE_PCH_HEADERS
  <deal.II/base/mpi.h>
  <deal.II/base/parameter_handler.h>
  <deal.II/base/point.h>
  <deal.II/base/quadrature_lib.h>
  <deal.II/base/function.h>
  <deal.II/base/symmetric_tensor.h>
  <deal.II/base/tensor.h>
  <deal.II/distributed/tria.h>
  <deal.II/dofs/dof_handler.h>
  <deal.II/dofs/dof_tools.h>
  <deal.II/fe/fe_q.h>
  <deal.II/fe/fe_system.h>
  <deal.II/fe/fe_values.h>
  <deal.II/fe/mapping_q.h>
  <deal.II/grid/grid_tools.h>
  <deal.II/grid/tria.h>
  <deal.II/lac/affine_constraints.h>
  <deal.II/lac/full_matrix.h>
  <deal.II/lac/petsc_vector.h>
  <deal.II/lac/vector.h>
  <deal.II/numerics/data_out.h>
  <map>
  <memory>
  <string>
  <vector>)

# systole_precompile_headers(target [more headers...]): the shared set (and the extra headers)
# precompiled for the target. Sources with their own macros or code-generation options before
# their includes opt out with the source property SKIP_PRECOMPILE_HEADERS.
function(systole_precompile_headers target)
  if(SYSTOLE_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${SYSTOLE_PCH_HEADERS} ${ARGN})
  endif()
endfunction()
