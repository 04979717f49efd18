#include "postprocess/aha_segments.h"

#include <deal.II/base/mpi.h>

#include "geometry/mesh.h"

#include <cmath>
#include <limits>

namespace systole::Postprocess
{
  namespace
  {
    /// The point of the vertices of the locally owned cells of @p wall (on
    /// faces of @p id, or all with id = invalid) farthest along -@p e from
    /// @p origin, over all ranks: its distance and position.
    std::pair<double, dealii::Point<3>>
    farthest(const dealii::Triangulation<3, 3> &tria,
             const LvWall                      &wall,
             const dealii::types::boundary_id   id,
             const dealii::Point<3>            &origin,
             const dealii::Tensor<1, 3>        &e)
    {
      double           best = -std::numeric_limits<double>::max();
      dealii::Point<3> where;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned() && wall.contains(cell))
          for (const unsigned int f : cell->face_indices())
            if (id == dealii::numbers::invalid_boundary_id ||
                (cell->face(f)->at_boundary() &&
                 cell->face(f)->boundary_id() == id))
              for (const unsigned int v : cell->face(f)->vertex_indices())
                {
                  const double d = -(cell->face(f)->vertex(v) - origin) * e;
                  if (d > best)
                    {
                      best  = d;
                      where = cell->face(f)->vertex(v);
                    }
                }
      const MPI_Comm comm   = tria.get_communicator();
      const double   global = dealii::Utilities::MPI::max(best, comm);
      // The lowest rank holding it reports the position.
      const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
      const unsigned int holder =
        dealii::Utilities::MPI::min(best == global
                                      ? rank
                                      : dealii::numbers::invalid_unsigned_int,
                                    comm);
      dealii::Tensor<1, 3> position;
      if (rank == holder)
        position = where;
      position = dealii::Utilities::MPI::sum(position, comm);
      return {global, dealii::Point<3>(position)};
    }
  } // namespace

  AhaSegments::AhaSegments(const Axis &axis)
    : geometry(axis)
    , binormal(dealii::cross_product_3d(-axis.direction, axis.reference))
  {}

  AhaSegments::Axis
  AhaSegments::axis_of(const dealii::Triangulation<3, 3> &tria,
                       const Geometry::BoundaryNames     &names,
                       const LvWall                      &wall,
                       const dealii::Tensor<1, 3>        &reference)
  {
    const auto base = Geometry::boundary_plane(tria, names.id("base"), "base");
    Axis       axis;
    // The normal's sign is arbitrary: the apex lies below the base.
    axis.direction        = base.normal / base.normal.norm();
    auto       far        = farthest(tria,
                        wall,
                        dealii::numbers::invalid_boundary_id,
                        base.point,
                        axis.direction);
    const auto other_side = farthest(tria,
                                     wall,
                                     dealii::numbers::invalid_boundary_id,
                                     base.point,
                                     -axis.direction);
    if (other_side.first > far.first)
      {
        axis.direction = -axis.direction;
        far            = other_side;
      }
    axis.apex   = far.second;
    axis.length = far.first;
    AssertThrow(axis.length > 0,
                dealii::ExcMessage("AHA segments: the mesh has no apex below "
                                   "its base plane."));
    const auto endo = farthest(tria,
                               wall,
                               names.id(wall.endocardium()),
                               base.point,
                               axis.direction);
    axis.cap_level  = 1.0 - endo.first / axis.length;
    const dealii::Tensor<1, 3> in_plane =
      reference - (reference * axis.direction) * axis.direction;
    AssertThrow(in_plane.norm() > 1e-6 * reference.norm() &&
                  reference.norm() > 0,
                dealii::ExcMessage(
                  "Postprocess / AHA segments / Reference direction must not "
                  "be parallel to the long axis of the ventricle (the base "
                  "plane's normal)."));
    axis.reference = in_plane / in_plane.norm();
    return axis;
  }

  const AhaSegments::Axis &
  AhaSegments::axis() const
  {
    return geometry;
  }

  double
  AhaSegments::level(const dealii::Point<3> &X) const
  {
    return (X - geometry.apex) * geometry.direction / geometry.length;
  }

  double
  AhaSegments::angle(const dealii::Point<3> &X) const
  {
    const dealii::Tensor<1, 3> r = X - geometry.apex;
    const double theta = std::atan2(r * binormal, r * geometry.reference);
    return theta < 0 ? theta + 2 * M_PI : theta;
  }

  unsigned int
  AhaSegments::ring(const double l) const
  {
    if (l < geometry.cap_level)
      return 0;
    const double t = (l - geometry.cap_level) / (1.0 - geometry.cap_level);
    return t < 1.0 / 3 ? 1 : (t < 2.0 / 3 ? 2 : 3);
  }

  unsigned int
  AhaSegments::segment(const dealii::Point<3> &X) const
  {
    const unsigned int r = ring(level(X));
    if (r == 0)
      return 17;
    const double degrees = angle(X) * 180 / M_PI;
    if (r == 1)
      return 13 +
             static_cast<unsigned int>(std::floor((degrees + 45) / 90)) % 4;
    const unsigned int k =
      static_cast<unsigned int>(std::floor((degrees + 30) / 60)) % 6;
    return (r == 3 ? 1 : 7) + k;
  }

  std::string
  AhaSegments::name(const unsigned int segment)
  {
    static const char *ring6[] = {"anterior",
                                  "anteroseptal",
                                  "inferoseptal",
                                  "inferior",
                                  "inferolateral",
                                  "anterolateral"};
    static const char *ring4[] = {"anterior", "septal", "inferior", "lateral"};
    AssertThrow(segment >= 1 && segment <= 17,
                dealii::ExcMessage("AHA segments are numbered 1 to 17."));
    if (segment <= 6)
      return std::string("basal ") + ring6[segment - 1];
    if (segment <= 12)
      return std::string("mid ") + ring6[segment - 7];
    if (segment <= 16)
      return std::string("apical ") + ring4[segment - 13];
    return "apex";
  }
} // namespace systole::Postprocess
