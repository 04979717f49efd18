#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/linear_algebra.h"
#include "geometry/mesh.h"
#include "mechanics/cavity_volume.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole;

namespace
{
  /// A smooth field that vanishes on the base plane z = 5, so that the basal
  /// ring stays in the lid plane.
  class BaseFixed : public dealii::Function<3>
  {
  public:
    BaseFixed(const double size, const double phase)
      : dealii::Function<3>(3)
      , size(size)
      , phase(phase)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return size * (5.0 - p[2]) / 20.0 *
             std::sin(0.3 * p[0] + phase * (c + 1)) *
             std::cos(0.2 * p[1] + 0.15 * p[2] - phase);
    }

  private:
    double size, phase;
  };
} // namespace

TEST_CASE("dV/du of the cavity is the finite-difference derivative of V",
          "[mechanics][fd]")
{
  Geometry::Parameters                            geometry; // Land ventricle
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto names = Geometry::create_mesh(geometry, tria);
  const auto lid   = Geometry::boundary_plane(tria, names.id("base"), "base");
  const unsigned int degree = GENERATE(1u, 2u);

  const dealii::FESystem<3> fe(dealii::FE_Q<3>(degree), 3);
  dealii::DoFHandler<3>     dof_handler(tria);
  dof_handler.distribute_dofs(fe);
  const dealii::MappingQ<3> mapping(2);
  const unsigned int        n_points = degree + 3;
  dealii::IndexSet          relevant;
  dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
  const auto &owned = dof_handler.locally_owned_dofs();

  LA::MPI::Vector u0(owned, MPI_COMM_WORLD), d(owned, MPI_COMM_WORLD);
  dealii::VectorTools::interpolate(mapping,
                                   dof_handler,
                                   BaseFixed(2.0, 0.4),
                                   u0);
  dealii::VectorTools::interpolate(mapping,
                                   dof_handler,
                                   BaseFixed(1.0, 1.1),
                                   d);

  const Mechanics::CavityVolume cavity(names.id("endocardium"), lid);
  LA::MPI::Vector               ghosted(owned, relevant, MPI_COMM_WORLD);
  const auto                    volume_at = [&](const double h) {
    LA::MPI::Vector v = u0;
    v.add(h, d);
    ghosted = v;
    return cavity.volume(mapping, dof_handler, ghosted, n_points);
  };

  ghosted = u0;
  LA::MPI::Vector dV_du(owned, MPI_COMM_WORLD);
  cavity.derivative(mapping, dof_handler, ghosted, n_points, dV_du);
  const double exact = dV_du * d;

  // V(u + h d) is a cubic polynomial in h (cof F is quadratic), so the
  // central difference has the error h^2 V'''/6: it falls by 4 per halving.
  double previous = 0;
  for (const double h : {0.2, 0.1, 0.05})
    {
      const double fd    = (volume_at(h) - volume_at(-h)) / (2 * h);
      const double error = std::abs(fd - exact) / std::abs(exact);
      INFO("Q" << degree << ", h = " << h << ": dV/du . d = " << exact
               << ", FD " << fd << ", relative error " << error);
      // Either exact to round-off (observed: about 1e-12), or the FD error
      // of a cubic (the first step size must then already be small).
      const bool exact = error < 1e-9;
      const bool second_order =
        error < 1e-3 &&
        (previous == 0 || std::abs(previous / error - 4.0) < 0.1);
      CHECK((exact || second_order));
      previous = error;
    }
}
