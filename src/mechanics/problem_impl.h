#pragma once

// Internal to src/mechanics: the state of Mechanics::Problem, shared by its
// translation units (problem.cc, assembly.cc). Not included elsewhere.

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/linear_algebra.h"
#include "base/logger.h"
#include "mechanics/cavity_volume.h"
#include "mechanics/linear_solver.h"
#include "mechanics/problem.h"

#include <optional>
#include <set>

namespace systole::Mechanics
{
  struct Problem::Impl
  {
    Impl(const Parameters                                   &params,
         dealii::parallel::distributed::Triangulation<3, 3> &tria,
         const Geometry::BoundaryNames                      &names,
         const unsigned int                                  degree,
         const unsigned int                                  mapping_degree,
         const Materials::PassiveLaw                        &passive_law,
         const Materials::VolumetricLaw                     &volumetric_law,
         Logger                                             &logger);

    /// Residual (and, if @p with_matrix, tangent) at the current u for the
    /// given loads. Returns the l2 norm of the constrained residual. Throws
    /// ExcInvertedElement collectively when J <= 0 somewhere.
    double
    assemble(const double pressure,
             const double active_tension,
             const bool   with_matrix);

    Parameters                                          params;
    dealii::parallel::distributed::Triangulation<3, 3> &tria;
    MPI_Comm                                            comm;
    Logger                                             &logger;
    const Materials::PassiveLaw                        &passive_law;
    const Materials::VolumetricLaw                     &volumetric_law;

    dealii::FESystem<3>   fe;
    dealii::MappingQ<3>   mapping;
    dealii::DoFHandler<3> dof_handler;
    unsigned int          n_q_1d;      ///< Gauss points per direction (cells)
    unsigned int          n_q_face_1d; ///< Gauss points per direction (faces)
    bool reduced_volumetric; ///< volumetric term with n_q_1d - 1 points

    dealii::IndexSet                  owned, relevant;
    dealii::AffineConstraints<double> constraints; ///< homogeneous

    std::set<dealii::types::boundary_id>      fixed_ids, sliding_ids, robin_ids;
    std::optional<dealii::types::boundary_id> pressure_id;
    std::optional<CavityVolume>               cavity;

    /// Fibre frames per locally owned cell (active_cell_index) and point.
    std::vector<std::vector<Fibres::FibreBasis>> fibre_bases;

    LA::MPI::SparseMatrix tangent;
    LA::MPI::Vector       residual;   ///< owned
    LA::MPI::Vector       u_owned;    ///< owned
    LA::MPI::Vector       u;          ///< ghosted copy of u_owned
    LA::MPI::Vector       u_saved;    ///< owned
    LA::MPI::Vector       u_previous; ///< owned, the save() before u_saved
    unsigned int          n_saves = 0;

    std::unique_ptr<LinearSolver> linear_solver;
  };
} // namespace systole::Mechanics
