#include "postprocess/lv_wall.h"

#include <deal.II/base/mpi.h>

#include "base/logger.h"
#include "fibres/laplace_fields.h"
#include "geometry/mesh.h"

#include <chrono>
#include <iomanip>
#include <optional>
#include <sstream>

namespace systole::Postprocess
{
  namespace
  {
    /// The fields of two ventricles, in LaplaceFields' order.
    enum Field : unsigned int
    {
      lv_transmural    = 0,
      apicobasal       = 1,
      interventricular = 2,
      septal           = 3,
      epi_transmural   = 4
    };
  } // namespace

  struct LvWall::Impl
  {
    explicit Impl(const dealii::Triangulation<3, 3> &tria)
      : tria(tria)
    {}

    const dealii::Triangulation<3, 3>                   &tria;
    bool                                                 two_ventricles = false;
    std::string                                          endo;
    std::vector<std::string>                             outer;
    std::optional<Fibres::WallCoordinates>               left;
    std::unique_ptr<Fibres::LaplaceFields>               fields;
    std::vector<bool>                                    in_wall;
    dealii::Point<3>                                     rv_centroid;
    mutable std::vector<std::vector<Fibres::FieldValue>> values;
  };

  namespace
  {
    /// The mean of the centres of the boundary faces with id @p id
    /// (collective).
    dealii::Point<3>
    face_centre_mean(const dealii::Triangulation<3, 3> &tria,
                     const dealii::types::boundary_id   id)
    {
      dealii::Tensor<1, 3> sum;
      double               count = 0;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == id)
              {
                sum += face->center();
                count += 1;
              }
      const MPI_Comm comm = tria.get_communicator();
      sum                 = dealii::Utilities::MPI::sum(sum, comm);
      count               = dealii::Utilities::MPI::sum(count, comm);
      return dealii::Point<3>(sum / count);
    }
  } // namespace

  LvWall::LvWall(const dealii::Triangulation<3, 3> &tria,
                 const Geometry::BoundaryNames     &names,
                 const bool                         frames,
                 Logger                            *logger)
    : impl(std::make_unique<Impl>(tria))
  {
    Impl &m = *impl;
    AssertThrow(
      names.has("endocardium") || names.has("lv_endocardium"),
      dealii::ExcMessage(
        "Postprocess / List of postprocessors: strain, AHA segments, clinical "
        "kinematics and ventricle function need a left ventricle (boundary "
        "parts endocardium, epicardium, base) or two ventricles "
        "(lv_endocardium, rv_endocardium, epicardium, base), but " +
        names.source() +
        " has no boundary part named 'endocardium' or 'lv_endocardium'."));
    m.two_ventricles = !names.has("endocardium");
    const std::vector<std::string> parts =
      m.two_ventricles
        ? std::vector<std::string>{"lv_endocardium",
                                   "rv_endocardium",
                                   "epicardium",
                                   "base"}
        : std::vector<std::string>{"endocardium", "epicardium", "base"};
    Geometry::require_boundaries(
      tria,
      names,
      parts,
      "Postprocess / List of postprocessors: strain, AHA segments, clinical "
      "kinematics and ventricle function need a " +
        std::string(m.two_ventricles ? "biventricular mesh"
                                     : "left ventricle"));
    m.endo  = parts[0];
    m.outer = m.two_ventricles
                ? std::vector<std::string>{"epicardium", "rv_endocardium"}
                : std::vector<std::string>{"epicardium"};
    if (!m.two_ventricles)
      {
        if (frames)
          m.left.emplace(Fibres::WallCoordinates::Parameters(),
                         tria,
                         names,
                         logger);
        return;
      }

    const auto start   = std::chrono::steady_clock::now();
    const auto lv_endo = names.id("lv_endocardium"),
               rv_endo = names.id("rv_endocardium"),
               epi = names.id("epicardium"), base = names.id("base");
    std::vector<Fibres::LaplaceProblem> problems(5);
    problems[lv_transmural]    = {"LV transmural",
                                  {{lv_endo, 0.0}, {rv_endo, 1.0}, {epi, 1.0}},
                                  0.0};
    problems[apicobasal]       = {"apicobasal", {{base, 0.0}}, 1.0};
    problems[interventricular] = {"interventricular",
                                  {{lv_endo, 0.0}, {rv_endo, 1.0}},
                                  0.0};
    problems[septal]           = {"septal", {{lv_endo, 1.0}, {epi, 0.0}}, 0.0};
    problems[epi_transmural]   = {"epicardial transmural",
                                  {{lv_endo, 0.0}, {rv_endo, 0.0}, {epi, 1.0}},
                                  0.0};
    m.fields = std::make_unique<Fibres::LaplaceFields>(tria, 2, problems);
    // psi = 1 - u / max u, as WallCoordinates.
    const double u_max = m.fields->maximum(apicobasal).first;
    AssertThrow(u_max > 0,
                dealii::ExcMessage("Postprocess: the apicobasal solve of the "
                                   "LV wall gave no positive values."));
    m.fields->scale(apicobasal, -1.0 / u_max, 1.0);

    // The cells of the LV wall, by the coordinates at their centres.
    m.in_wall.assign(tria.n_active_cells(), false);
    unsigned int n_wall = 0, n_cells = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (!cell->is_artificial())
        {
          m.fields->evaluate(cell, {cell->center()}, m.values);
          const bool rv_free_wall = m.values[interventricular][0].value > 0.5 &&
                                    m.values[septal][0].value < 0.5;
          m.in_wall[cell->active_cell_index()] = !rv_free_wall;
          if (cell->is_locally_owned())
            {
              n_wall += rv_free_wall ? 0 : 1;
              ++n_cells;
            }
        }
    const MPI_Comm comm = tria.get_communicator();
    n_wall              = dealii::Utilities::MPI::sum(n_wall, comm);
    n_cells             = dealii::Utilities::MPI::sum(n_cells, comm);

    // The RV's side.
    m.rv_centroid = face_centre_mean(tria, rv_endo);

    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    std::ostringstream o;
    o << std::fixed << std::setprecision(2) << "Postprocess: the LV wall of "
      << "the two ventricles is " << n_wall << " of " << n_cells
      << " cells (LV free wall and septum); " << m.fields->element_name()
      << ", " << m.fields->n_dofs() << " DOFs per solve, 5 solves, " << seconds
      << " s";
    if (logger != nullptr)
      logger->line(o.str());
  }

  LvWall::~LvWall() = default;

  bool
  LvWall::biventricular() const
  {
    return impl->two_ventricles;
  }

  const std::string &
  LvWall::endocardium() const
  {
    return impl->endo;
  }

  const std::vector<std::string> &
  LvWall::outer_surface() const
  {
    return impl->outer;
  }

  bool
  LvWall::contains(const dealii::Triangulation<3, 3>::cell_iterator &cell) const
  {
    return impl->in_wall.empty() || impl->in_wall[cell->active_cell_index()];
  }

  const std::vector<bool> &
  LvWall::cells() const
  {
    return impl->in_wall;
  }

  void
  LvWall::frames(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
                 const std::vector<dealii::Point<3>> &points,
                 std::vector<Fibres::WallFrame>      &result) const
  {
    const Impl &m = *impl;
    if (!m.two_ventricles)
      {
        AssertThrow(m.left.has_value(),
                    dealii::ExcMessage("Postprocess: the LV wall was built "
                                       "without frames."));
        m.left->evaluate(cell, points, result);
        return;
      }
    m.fields->evaluate(cell, points, m.values);
    const unsigned int transmural =
      contains(cell) ? lv_transmural : epi_transmural;
    result.resize(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      result[i] = Fibres::wall_frame(m.values[transmural][i],
                                     m.values[apicobasal][i],
                                     points[i],
                                     "Postprocess: the LV wall's frame");
  }

  const dealii::Point<3> &
  LvWall::rv_centroid() const
  {
    AssertThrow(impl->two_ventricles,
                dealii::ExcMessage("Postprocess: a left ventricle has no "
                                   "RV."));
    return impl->rv_centroid;
  }
} // namespace systole::Postprocess
