#include "mechanics/p_multigrid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/full_matrix.h>

#include "mechanics/field_layout.h"
#include "mechanics/petsc_tools.h"

#include <petscksp.h>

#include <array>
#include <cmath>
#include <vector>

namespace systole::Mechanics
{
  namespace
  {
    /// Whether the locally owned DoFs of a Q1^3 DoFHandler come as (x, y, z)
    /// triples of one vertex, aligned at multiples of 3 (collective).
    bool
    interleaved(const dealii::DoFHandler<3, 3> &dof_handler)
    {
      const auto &owned = dof_handler.locally_owned_dofs();
      const auto  n     = owned.n_elements();
      bool        ok    = n % 3 == 0 && (n == 0 || owned.is_contiguous());
      const dealii::types::global_dof_index first = n == 0 ? 0 : *owned.begin();
      std::vector<dealii::types::global_dof_index> dofs(
        dof_handler.get_fe().n_dofs_per_cell());
      const auto &fe = dof_handler.get_fe();
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (ok && cell->is_locally_owned())
          {
            cell->get_dof_indices(dofs);
            for (unsigned int v = 0; v < cell->n_vertices(); ++v)
              {
                const auto d0 = dofs[fe.component_to_system_index(0, v)];
                if (!owned.is_element(d0))
                  continue;
                ok = ok && (d0 - first) % 3 == 0 &&
                     dofs[fe.component_to_system_index(1, v)] == d0 + 1 &&
                     dofs[fe.component_to_system_index(2, v)] == d0 + 2;
              }
          }
      return dealii::Utilities::MPI::min(ok ? 1 : 0,
                                         dof_handler.get_communicator()) == 1;
    }
  } // namespace

  struct PMultigrid::Impl
  {
    MPI_Comm     comm;
    std::string  prefix;
    unsigned int degree = 2;
    /// Interpolation: fine displacement block <- Q1 displacement.
    Mat P = nullptr;
    /// The six rigid-body modes of the Q1 space.
    MatNullSpace coarse_modes = nullptr;
    /// The Galerkin product P^T A P of the last set-up, and that A.
    Mat A1 = nullptr, A = nullptr;
    PC  mg = nullptr;

    ~Impl()
    {
      PCDestroy(&mg);
      MatDestroy(&A1);
      MatDestroy(&P);
      MatNullSpaceDestroy(&coarse_modes);
    }

    /// The two-level cycle for the operator @p fine.
    void
    setup(Mat fine)
    {
      // A new operator object (not the values of the old one): start afresh
      // (the cycle's residual and the product hold the old one).
      if (fine != A)
        {
          PCDestroy(&mg);
          MatDestroy(&A1);
          A = fine;
        }
      check_petsc(MatPtAP(fine,
                          P,
                          A1 == nullptr ? MAT_INITIAL_MATRIX : MAT_REUSE_MATRIX,
                          PETSC_DEFAULT,
                          &A1),
                  "MatPtAP");
      // (The product has the column block size of P: 3 for interleaved
      // nodes, as GAMG needs with the six modes.)
      check_petsc(MatSetNearNullSpace(A1, coarse_modes), "MatSetNearNullSpace");
      if (mg == nullptr)
        {
          check_petsc(PCCreate(comm, &mg), "PCCreate");
          check_petsc(PCSetOptionsPrefix(mg, prefix.c_str()),
                      "PCSetOptionsPrefix");
          check_petsc(PCSetType(mg, PCMG), "PCSetType");
          check_petsc(PCMGSetLevels(mg, 2, nullptr), "PCMGSetLevels");
          check_petsc(PCMGSetType(mg, PC_MG_MULTIPLICATIVE), "PCMGSetType");
          check_petsc(PCMGSetCycleType(mg, PC_MG_CYCLE_V), "PCMGSetCycleType");
          check_petsc(PCMGSetGalerkin(mg, PC_MG_GALERKIN_NONE),
                      "PCMGSetGalerkin");
          check_petsc(PCSetFromOptions(mg), "PCSetFromOptions");
          check_petsc(PCMGSetInterpolation(mg, 1, P), "PCMGSetInterpolation");
        }
      KSP level;
      check_petsc(PCMGGetCoarseSolve(mg, &level), "PCMGGetCoarseSolve");
      check_petsc(KSPSetOperators(level, A1, A1), "KSPSetOperators");
      check_petsc(PCMGGetSmoother(mg, 1, &level), "PCMGGetSmoother");
      check_petsc(KSPSetOperators(level, fine, fine), "KSPSetOperators");
      check_petsc(PCSetOperators(mg, fine, fine), "PCSetOperators");
      check_petsc(PCSetUp(mg), "PCSetUp");
    }

    static PetscErrorCode
    shell_setup(PC pc)
    {
      Impl *self = nullptr;
      PetscCall(PCShellGetContext(pc, &self));
      Mat amat, pmat;
      PetscCall(PCGetOperators(pc, &amat, &pmat));
      try
        {
          self->setup(pmat);
        }
      catch (...)
        {
          return PETSC_ERR_LIB;
        }
      return 0;
    }

    static PetscErrorCode
    shell_apply(PC pc, Vec x, Vec y)
    {
      Impl *self = nullptr;
      PetscCall(PCShellGetContext(pc, &self));
      PetscCall(PCApply(self->mg, x, y));
      return 0;
    }

    static PetscErrorCode
    shell_view(PC pc, PetscViewer viewer)
    {
      Impl *self = nullptr;
      PetscCall(PCShellGetContext(pc, &self));
      if (self->mg != nullptr)
        PetscCall(PCView(self->mg, viewer));
      return 0;
    }
  };

  namespace
  {
    /// The interpolation of one scalar component, Q1 -> Q_k, on the unit
    /// cell (the same on every cell: the map is the reference-cell one).
    /// Nodal interpolation: coarse shape functions at the fine support
    /// points (what FE_Q::get_interpolation_matrix() gives; FE_SimplexP has
    /// none).
    dealii::FullMatrix<double>
    unit_interpolation(const dealii::FiniteElement<3, 3> &fine_base,
                       const dealii::FiniteElement<3, 3> &q1)
    {
      dealii::FullMatrix<double> interpolation(fine_base.n_dofs_per_cell(),
                                               q1.n_dofs_per_cell());
      const auto &fine_points = fine_base.get_unit_support_points();
      for (unsigned int k = 0; k < fine_points.size(); ++k)
        for (unsigned int l = 0; l < q1.n_dofs_per_cell(); ++l)
          interpolation(k, l) = q1.shape_value(l, fine_points[k]);
      return interpolation;
    }

    /// The rows of the interpolation P from the Q1 displacement @p dof_q1 to
    /// the owned displacement DoFs of @p dof_handler, rows from @p offset
    /// (into the created, preallocated @p P).
    void
    fill_interpolation(const dealii::DoFHandler<3, 3>          &dof_handler,
                       const dealii::DoFHandler<3>             &dof_q1,
                       const FieldLayout                       &layout,
                       const dealii::AffineConstraints<double> &constraints,
                       const PetscInt                           offset,
                       Mat                                      P)
    {
      const auto        &fe            = dof_handler.get_fe();
      const auto        &fe_q1         = dof_q1.get_fe();
      const auto        &q1            = fe_q1.base_element(0);
      const auto        &fine_base     = fe.base_element(0);
      const auto         interpolation = unit_interpolation(fine_base, q1);
      const unsigned int n_vertex_dofs = fine_base.get_first_line_index();
      const auto        &owned_u       = layout.owned(0);
      const PetscInt     n_u           = owned_u.n_elements();
      const dealii::types::global_dof_index u0 = n_u > 0 ? *owned_u.begin() : 0;
      std::vector<bool>                     done(n_u, false);
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell()),
        dofs_q1(fe_q1.n_dofs_per_cell());
      std::vector<PetscInt>    columns;
      std::vector<PetscScalar> values;
      auto                     cell_q1 = dof_q1.begin_active();
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          if (cell->is_locally_owned())
            {
              cell->get_dof_indices(dofs);
              cell_q1->get_dof_indices(dofs_q1);
              for (unsigned int i = 0; i < dofs.size(); ++i)
                {
                  const auto [c, k] = fe.system_to_component_index(i);
                  if (c >= 3 || !owned_u.is_element(dofs[i]) ||
                      done[dofs[i] - u0])
                    continue;
                  done[dofs[i] - u0] = true;
                  // A constrained DoF is decoupled in the tangent: only a
                  // vertex keeps its coarse vertex (the row of the identity).
                  if (constraints.is_constrained(dofs[i]) && k >= n_vertex_dofs)
                    continue;
                  columns.clear();
                  values.clear();
                  for (unsigned int l = 0; l < q1.n_dofs_per_cell(); ++l)
                    if (std::abs(interpolation(k, l)) > 1e-12)
                      {
                        columns.push_back(
                          dofs_q1[fe_q1.component_to_system_index(c, l)]);
                        values.push_back(interpolation(k, l));
                      }
                  const PetscInt row = offset + (dofs[i] - u0);
                  check_petsc(MatSetValues(P,
                                           1,
                                           &row,
                                           columns.size(),
                                           columns.data(),
                                           values.data(),
                                           INSERT_VALUES),
                              "MatSetValues");
                }
            }
          ++cell_q1;
        }
      check_petsc(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check_petsc(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    }

    /// The interpolation P from the Q1 displacement @p dof_q1 to the
    /// displacement block of @p dof_handler (a PETSc matrix of this rank's
    /// owned rows).
    Mat
    interpolation_matrix(const dealii::DoFHandler<3, 3>          &dof_handler,
                         const dealii::DoFHandler<3>             &dof_q1,
                         const FieldLayout                       &layout,
                         const dealii::AffineConstraints<double> &constraints,
                         const MPI_Comm                           comm)
    {
      // Rows: the owned displacement DoFs [u0, u0 + n_u) of this rank are
      // rows [offset, offset + n_u) of the displacement block.
      const PetscInt n_u    = layout.owned(0).n_elements();
      PetscInt       offset = 0;
      MPI_Exscan(&n_u, &offset, 1, MPIU_INT, MPI_SUM, comm);
      if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        offset = 0;
      const PetscInt n_coarse = dof_q1.locally_owned_dofs().n_elements();

      Mat P;
      check_petsc(MatCreate(comm, &P), "MatCreate");
      check_petsc(
        MatSetSizes(P, n_u, n_coarse, PETSC_DETERMINE, PETSC_DETERMINE),
        "MatSetSizes");
      check_petsc(MatSetBlockSizes(P,
                                   layout.displacement_interleaved() ? 3 : 1,
                                   interleaved(dof_q1) ? 3 : 1),
                  "MatSetBlockSizes");
      // MPIAIJ also on one rank: the tangent is one (PETSc multiplies like
      // types only).
      check_petsc(MatSetType(P, MATMPIAIJ), "MatSetType");
      // A row of one component interpolates the (up to 8) vertices of a
      // cell.
      const PetscInt per_row =
        dof_q1.get_fe().base_element(0).n_dofs_per_cell();
      check_petsc(
        MatMPIAIJSetPreallocation(P, per_row, nullptr, per_row, nullptr),
        "MatMPIAIJSetPreallocation");
      fill_interpolation(dof_handler, dof_q1, layout, constraints, offset, P);
      return P;
    }

    /// The rigid-body modes of the coarse space @p dof_q1 as PETSc's null
    /// space (PETSc keeps its own copies), in vectors like the columns of
    /// @p P.
    MatNullSpace
    coarse_null_space(const dealii::Mapping<3, 3> &mapping,
                      const dealii::DoFHandler<3> &dof_q1,
                      const Mat                    P,
                      const MPI_Comm               comm)
    {
      const auto         modes = rigid_body_modes(mapping, dof_q1);
      std::array<Vec, 6> vectors;
      for (unsigned int i = 0; i < modes.size(); ++i)
        {
          check_petsc(MatCreateVecs(P, &vectors[i], nullptr), "MatCreateVecs");
          check_petsc(VecCopy(modes[i], vectors[i]), "VecCopy");
        }
      MatNullSpace space;
      check_petsc(MatNullSpaceCreate(comm,
                                     PETSC_FALSE,
                                     vectors.size(),
                                     vectors.data(),
                                     &space),
                  "MatNullSpaceCreate");
      for (auto &v : vectors)
        VecDestroy(&v);
      return space;
    }

    /// Defaults, unless given in PETSc's options database (the measurements
    /// behind them: docs/architecture.md). Fine level: three Chebyshev
    /// iterations with point-block Jacobi (as good as GMRES or SOR
    /// smoothing, and cheaper). Coarse level: an exact solve, MUMPS LU of
    /// the Q1 operator (an eighth of the fine displacement DoFs, with a
    /// quarter of the entries per row). One GAMG V-cycle there lost the
    /// Newton iterate after the first update of a load step of Land problem
    /// 2 (779 Krylov iterations for one solve at 128 731 DoFs, 96 with LU;
    /// 414 and 67 at 17 903). With <prefix>mg_coarse_pc_type gamg, GAMG is
    /// smoothed as the GAMG of the "amg" choice, two GMRES-Jacobi iterations
    /// (Chebyshev-SOR breaks down in GAMG's eigenvalue estimate on the
    /// ventricle refined twice).
    void
    set_default_options(const std::string &prefix)
    {
      const std::string p = "-" + prefix;
      set_default_petsc_option(p + "mg_levels_ksp_type", "chebyshev");
      set_default_petsc_option(p + "mg_levels_ksp_max_it", "3");
      set_default_petsc_option(p + "mg_levels_pc_type", "pbjacobi");
      set_default_petsc_option(p + "mg_coarse_ksp_type", "preonly");
      set_default_petsc_option(p + "mg_coarse_pc_type", "lu");
      set_default_petsc_option(p + "mg_coarse_pc_factor_mat_solver_type",
                               "mumps");
      set_default_petsc_option(p + "mg_coarse_mg_levels_ksp_type", "gmres");
      set_default_petsc_option(p + "mg_coarse_mg_levels_ksp_max_it", "2");
      set_default_petsc_option(p + "mg_coarse_mg_levels_pc_type", "jacobi");
    }
  } // namespace

  bool
  PMultigrid::applicable(const dealii::DoFHandler<3, 3> &dof_handler)
  {
    return dof_handler.get_fe().base_element(0).degree > 1;
  }

  PMultigrid::PMultigrid(const dealii::Mapping<3, 3>             &mapping,
                         const dealii::DoFHandler<3, 3>          &dof_handler,
                         const FieldLayout                       &layout,
                         const dealii::AffineConstraints<double> &constraints,
                         const std::string                       &prefix)
    : impl(std::make_unique<Impl>())
  {
    Impl &m  = *impl;
    m.comm   = dof_handler.get_communicator();
    m.prefix = prefix;
    m.degree = dof_handler.get_fe().base_element(0).degree;
    AssertThrow(applicable(dof_handler),
                dealii::ExcMessage("p-multigrid needs a displacement of "
                                   "degree 2 or more."));

    // The coarse space: Q1^3 on the same mesh (deal.II numbers the DoFs of a
    // vertex consecutively, so its owned DoFs are node triples).
    const auto                q1_storage = layout.cell_kind().lagrange(1);
    const dealii::FESystem<3> fe_q1(*q1_storage, 3);
    dealii::DoFHandler<3>     dof_q1(dof_handler.get_triangulation());
    dof_q1.distribute_dofs(fe_q1);
    m.P =
      interpolation_matrix(dof_handler, dof_q1, layout, constraints, m.comm);
    m.coarse_modes = coarse_null_space(mapping, dof_q1, m.P, m.comm);
    set_default_options(prefix);
  }

  PMultigrid::~PMultigrid() = default;

  void
  PMultigrid::attach(PC pc)
  {
    check_petsc(PCSetType(pc, PCSHELL), "PCSetType");
    check_petsc(PCShellSetContext(pc, impl.get()), "PCShellSetContext");
    check_petsc(PCShellSetSetUp(pc, &Impl::shell_setup), "PCShellSetSetUp");
    check_petsc(PCShellSetApply(pc, &Impl::shell_apply), "PCShellSetApply");
    check_petsc(PCShellSetView(pc, &Impl::shell_view), "PCShellSetView");
    check_petsc(PCShellSetName(pc, "p-multigrid"), "PCShellSetName");
  }

  std::string
  PMultigrid::name() const
  {
    // What the options database holds now (the defaults or the user's).
    const auto option = [&](const std::string &name) {
      char      value[64] = "";
      PetscBool set       = PETSC_FALSE;
      PetscOptionsGetString(nullptr,
                            impl->prefix.c_str(),
                            ("-" + name).c_str(),
                            value,
                            sizeof(value),
                            &set);
      return set ? std::string(value) : std::string("default");
    };
    return "p-multigrid Q" + std::to_string(impl->degree) + " -> Q1 (" +
           option("mg_levels_ksp_max_it") + " x " +
           option("mg_levels_ksp_type") + " + " + option("mg_levels_pc_type") +
           "; " + option("mg_coarse_pc_type") + " on Q1)";
  }
} // namespace systole::Mechanics
