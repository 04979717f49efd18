#include "mechanics/petsc_tools.h"

#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>

#include <petscsys.h>

#include <algorithm>
#include <string>

namespace systole::Mechanics
{
  void
  set_near_null_space(Mat A, const std::array<LA::MPI::Vector, 6> &modes)
  {
    std::array<Vec, 6> vectors;
    for (unsigned int i = 0; i < 6; ++i)
      vectors[i] = modes[i];
    MatNullSpace near_null_space;
    check_petsc(MatNullSpaceCreate(modes[0].get_mpi_communicator(),
                                   PETSC_FALSE,
                                   6,
                                   vectors.data(),
                                   &near_null_space),
                "MatNullSpaceCreate");
    check_petsc(MatSetNearNullSpace(A, near_null_space), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&near_null_space);
  }

  void
  check_petsc(const PetscErrorCode code, const char *what)
  {
    AssertThrow(code == 0,
                dealii::ExcMessage(std::string("PETSc failed in ") + what +
                                   " (error code " + std::to_string(code) +
                                   ")."));
  }

  void
  copy_owned(const LA::MPI::Vector                              &from,
             dealii::LinearAlgebra::distributed::Vector<double> &to)
  {
    AssertThrow(static_cast<std::size_t>(from.locally_owned_size()) ==
                  to.locally_owned_size(),
                dealii::ExcInternalError());
    const PetscScalar *x;
    check_petsc(VecGetArrayRead(from, &x), "VecGetArrayRead");
    std::copy(x, x + to.locally_owned_size(), to.begin());
    check_petsc(VecRestoreArrayRead(from, &x), "VecRestoreArrayRead");
  }


  void
  copy_owned(const dealii::LinearAlgebra::distributed::Vector<double> &from,
             LA::MPI::Vector                                          &to)
  {
    AssertThrow(static_cast<std::size_t>(to.locally_owned_size()) ==
                  from.locally_owned_size(),
                dealii::ExcInternalError());
    PetscScalar *x;
    check_petsc(VecGetArray(to, &x), "VecGetArray");
    std::copy(from.begin(), from.begin() + from.locally_owned_size(), x);
    check_petsc(VecRestoreArray(to, &x), "VecRestoreArray");
  }


  std::array<LA::MPI::Vector, 6>
  rigid_body_modes(const dealii::Mapping<3, 3>    &mapping,
                   const dealii::DoFHandler<3, 3> &dof_handler)
  {
    std::array<LA::MPI::Vector, 6> modes;
    const MPI_Comm                 comm  = dof_handler.get_communicator();
    const auto                    &owned = dof_handler.locally_owned_dofs();
    for (auto &mode : modes)
      mode.reinit(owned, comm);

    // Position of the support point of every displacement DoF: the unit
    // support points of the displacement's base element (FE_Q).
    const auto                 &fe = dof_handler.get_fe();
    const dealii::Quadrature<3> support(
      fe.base_element(0).get_unit_support_points());
    dealii::FEValues<3>                          fe_values(mapping,
                                  fe,
                                  support,
                                  dealii::update_quadrature_points);
    std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto [c, base_index] = fe.system_to_component_index(i);
              if (c >= 3 || !owned.is_element(dofs[i]))
                continue;
              const auto &x     = fe_values.quadrature_point(base_index);
              modes[c](dofs[i]) = 1.0; // translations
              // rotations about the axes: (e_k x x)_c = eps_{c k m} x_m,
              // nonzero for k = c1 (x_c2) and k = c2 (-x_c1).
              const unsigned int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
              modes[3 + c1](dofs[i]) = x[c2];
              modes[3 + c2](dofs[i]) = -x[c1];
            }
        }
    for (auto &mode : modes)
      mode.compress(dealii::VectorOperation::insert);
    // Modified Gram-Schmidt.
    for (unsigned int i = 0; i < modes.size(); ++i)
      {
        for (unsigned int j = 0; j < i; ++j)
          modes[i].add(-(modes[i] * modes[j]), modes[j]);
        modes[i] /= modes[i].l2_norm();
      }
    return modes;
  }

  void
  set_default_petsc_option(const std::string &name, const std::string &value)
  {
    PetscBool set = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set);
    if (!set)
      check_petsc(PetscOptionsSetValue(nullptr, name.c_str(), value.c_str()),
                  "PetscOptionsSetValue");
  }
} // namespace systole::Mechanics
