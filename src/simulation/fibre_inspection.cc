#include "simulation/fibre_inspection.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/numerics/data_component_interpretation.h>
#include <deal.II/numerics/data_out.h>

#include "base/linear_algebra.h"
#include "base/logger.h"
#include "fibres/biventricular.h"
#include "fibres/fibre_field.h"
#include "fibres/rule_based.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "simulation/parameters.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>

namespace systole
{
  namespace
  {
    constexpr double degree = M_PI / 180.0;

    /// The helix-angle profile through the wall, summed over all ranks.
    struct Profile
    {
      std::vector<double> weight, weighted_sum, min, max, count;

      Profile()
        : weight(n_helix_profile_bins, 0.0)
        , weighted_sum(n_helix_profile_bins, 0.0)
        , min(n_helix_profile_bins, std::numeric_limits<double>::max())
        , max(n_helix_profile_bins, -std::numeric_limits<double>::max())
        , count(n_helix_profile_bins, 0.0)
      {}

      void
      add(const double depth, const double angle, const double JxW)
      {
        const auto bin = static_cast<unsigned int>(
          std::min<double>(n_helix_profile_bins - 1,
                           std::max(0.0, depth) * n_helix_profile_bins));
        weight[bin] += JxW;
        weighted_sum[bin] += JxW * angle;
        min[bin] = std::min(min[bin], angle);
        max[bin] = std::max(max[bin], angle);
        count[bin] += 1;
      }

      void
      reduce(const MPI_Comm comm)
      {
        dealii::Utilities::MPI::sum(weight, comm, weight);
        dealii::Utilities::MPI::sum(weighted_sum, comm, weighted_sum);
        dealii::Utilities::MPI::sum(count, comm, count);
        dealii::Utilities::MPI::min(min, comm, min);
        dealii::Utilities::MPI::max(max, comm, max);
      }
    };

    /// The parameter text recorded in the results file (as `systole` does).
    std::string
    parameter_text(const dealii::ParameterHandler &prm, const std::string &file)
    {
      std::ifstream      in(file);
      std::ostringstream text;
      text << "# Parameter file '" << file << "' as given:\n"
           << in.rdbuf() << "\n# All entries with the values used:\n";
      prm.print_parameters(text, dealii::ParameterHandler::ShortPRM);
      return text.str();
    }

    /// The wall frame to measure helix angles in (see the header): on LV
    /// meshes the rule-based generator's WallCoordinates, on BiV meshes the
    /// transmural and apicobasal fields of the biventricular rule
    /// (Biventricular::wall_frames); none on other meshes.
    struct WallMeasure
    {
      std::unique_ptr<Fibres::WallCoordinates> lv_wall;
      std::unique_ptr<Fibres::Biventricular>   biv_wall;
      /// Fibres from a diffusion tensor have no sign (dti_import.h): f and
      /// -f are the same fibre, so their angle is folded into (-90, 90].
      /// The biventricular rule interpolates axes (bislerp): no sign either.
      bool signless = false;

      bool
      exists() const
      {
        return lv_wall || biv_wall;
      }

      void
      frames(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const std::vector<dealii::Point<3>>                     &points,
             std::vector<Fibres::WallFrame> &frames) const
      {
        if (lv_wall)
          lv_wall->evaluate(cell, points, frames);
        else
          biv_wall->wall_frames(cell, points, frames);
      }

      /// The helix angle [degree] of @p f in @p frame.
      double
      helix_angle(const dealii::Tensor<1, 3> &f,
                  const Fibres::WallFrame    &frame) const
      {
        double angle = Fibres::helix_angle(f, frame.e_c, frame.e_l) / degree;
        if (signless && angle > 90.0)
          angle -= 180.0;
        else if (signless && angle <= -90.0)
          angle += 180.0;
        return angle;
      }
    };

    /// The wall frame of the mesh's boundary parts (none, with a line
    /// saying so, on a mesh that is neither an LV nor a BiV).
    WallMeasure
    wall_measure(const Fibres::Parameters       &fibres,
                 const dealii::Triangulation<3> &tria,
                 const Geometry::BoundaryNames  &names,
                 Logger                         &logger)
    {
      WallMeasure wall;
      if (names.has("endocardium") && names.has("epicardium") &&
          names.has("base"))
        wall.lv_wall =
          std::make_unique<Fibres::WallCoordinates>(fibres.rule_based,
                                                    tria,
                                                    names);
      else if (names.has("lv_endocardium") && names.has("rv_endocardium") &&
               names.has("epicardium") && names.has("base"))
        wall.biv_wall =
          std::make_unique<Fibres::Biventricular>(fibres.biventricular,
                                                  tria,
                                                  names);
      else
        logger.line("The mesh has no boundary parts endocardium, epicardium "
                    "and base (or lv_endocardium, rv_endocardium, epicardium "
                    "and base): no helix-angle profile.");
      wall.signless = fibres.generator == "dti" ||
                      fibres.generator == Fibres::Biventricular::name;
      return wall;
    }

    /// The helix-angle profile at the Gauss points of every cell (empty
    /// without a wall frame; collective).
    Profile
    helix_profile(const dealii::parallel::DistributedTriangulationBase<3> &tria,
                  const Geometry::CellKind                                &kind,
                  const dealii::Mapping<3> &mapping,
                  const Fibres::FibreField &field,
                  const WallMeasure        &wall,
                  const MPI_Comm            comm)
    {
      Profile                         profile;
      std::vector<Fibres::FibreBasis> bases;
      std::vector<Fibres::WallFrame>  frames;
      const auto                      fe = kind.lagrange(1);
      dealii::FEValues<3>             fe_values(mapping,
                                    *fe,
                                    // QGaussSimplex has at most 4.
                                    kind.cell_quadrature(kind.simplex() ? 4
                                                                        : 5),
                                    dealii::update_quadrature_points |
                                      dealii::update_JxW_values);
      if (wall.exists())
        for (const auto &cell : tria.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              fe_values.reinit(cell);
              field(cell, fe_values.get_quadrature_points(), bases);
              wall.frames(cell, fe_values.get_quadrature_points(), frames);
              for (unsigned int q = 0; q < bases.size(); ++q)
                if (!frames[q].degenerate)
                  profile.add(frames[q].transmural,
                              wall.helix_angle(bases[q].f, frames[q]),
                              fe_values.JxW(q));
            }
      profile.reduce(comm);
      return profile;
    }

    /// The fields at the vertices of every cell as a discontinuous linear
    /// field: the support points of FE_DGQ(1) (hexahedra) and
    /// FE_SimplexDGP(1) (tetrahedra) are the vertices, in the cell's order.
    /// fibre, sheet, sheet_normal, and with a wall frame transmural,
    /// apicobasal and helix_angle.
    class VertexFields
    {
    public:
      VertexFields(const dealii::Triangulation<3> &tria,
                   const Geometry::CellKind       &kind,
                   const bool                      wall)
        : fe(make_fe(kind, wall))
        , dof_handler(tria)
      {
        for (const auto &name : {"fibre", "sheet", "sheet_normal"})
          names.insert(names.end(), 3, name);
        interpretation.assign(
          names.size(),
          dealii::DataComponentInterpretation::component_is_part_of_vector);
        if (wall)
          for (const std::string name :
               {"transmural", "apicobasal", "helix_angle"})
            {
              names.push_back(name);
              interpretation.push_back(
                dealii::DataComponentInterpretation::component_is_scalar);
            }
        dof_handler.distribute_dofs(fe);
      }

      /// The values of @p field (and @p wall's frame) at the vertices
      /// (collective).
      void
      compute(const Fibres::FibreField &field,
              const WallMeasure        &wall,
              const MPI_Comm            comm);

      /// The field into @p data_out.
      void
      attach(dealii::DataOut<3> &data_out) const
      {
        data_out.attach_dof_handler(dof_handler);
        data_out.add_data_vector(ghosted,
                                 names,
                                 dealii::DataOut<3>::type_dof_data,
                                 interpretation);
      }

    private:
      static dealii::FESystem<3>
      make_fe(const Geometry::CellKind &kind, const bool wall)
      {
        const unsigned int n = wall ? 12 : 9;
        return kind.simplex()
                 ? dealii::FESystem<3>(dealii::FE_SimplexDGP<3>(1), n)
                 : dealii::FESystem<3>(dealii::FE_DGQ<3>(1), n);
      }

      const dealii::FESystem<3> fe;
      dealii::DoFHandler<3>     dof_handler;
      std::vector<std::string>  names;
      std::vector<
        dealii::DataComponentInterpretation::DataComponentInterpretation>
                      interpretation;
      LA::MPI::Vector ghosted;
    };

    void
    VertexFields::compute(const Fibres::FibreField &field,
                          const WallMeasure        &wall,
                          const MPI_Comm            comm)
    {
      const dealii::IndexSet owned = dof_handler.locally_owned_dofs();
      dealii::IndexSet       relevant;
      dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      LA::MPI::Vector                              values(owned, comm);
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
      std::vector<dealii::Point<3>>                vertices;
      std::vector<Fibres::FibreBasis>              bases;
      std::vector<Fibres::WallFrame>               frames;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            vertices.resize(cell->n_vertices());
            for (const unsigned int v : cell->vertex_indices())
              vertices[v] = cell->vertex(v);
            field(cell, vertices, bases);
            if (wall.exists())
              wall.frames(cell, vertices, frames);
            cell->get_dof_indices(dofs);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              {
                const auto [c, v] = fe.system_to_component_index(i);
                const auto &b     = bases[v];
                double      value = 0;
                if (c < 3)
                  value = b.f[c];
                else if (c < 6)
                  value = b.s[c - 3];
                else if (c < 9)
                  value = b.n[c - 6];
                else if (c == 9)
                  value = frames[v].transmural;
                else if (c == 10)
                  value = frames[v].apicobasal;
                else
                  value = wall.helix_angle(b.f, frames[v]);
                values(dofs[i]) = value;
              }
          }
      values.compress(dealii::VectorOperation::insert);
      ghosted.reinit(owned, relevant, comm);
      ghosted = values;
    }

    /// The profile as the summary rows of @p results and as a table on the
    /// screen.
    void
    write_profile(const Profile   &profile,
                  IO::ResultsFile &results,
                  Logger          &logger)
    {
      std::ostringstream table;
      table << "Helix angle [degree] through the wall (depth: transmural "
               "coordinate, 0 endocardium, 1 epicardium):\n"
            << "  depth        mean     min     max  points\n";
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (unsigned int k = 0; k < n_helix_profile_bins; ++k)
        {
          const double lower = static_cast<double>(k) / n_helix_profile_bins;
          const double upper = (k + 1.0) / n_helix_profile_bins;
          const bool   empty = profile.count[k] == 0;
          const double mean =
            empty ? nan : profile.weighted_sum[k] / profile.weight[k];
          results.append_summary(
            {{"depth_lower", "-", lower},
             {"depth_upper", "-", upper},
             {"depth", "-", 0.5 * (lower + upper)},
             {"helix_mean", "degree", mean},
             {"helix_min", "degree", empty ? nan : profile.min[k]},
             {"helix_max", "degree", empty ? nan : profile.max[k]},
             {"n_points", "-", profile.count[k]}});
          table << std::fixed << std::setprecision(1) << "  " << lower << "-"
                << upper << std::setw(8) << mean << std::setw(8)
                << (empty ? nan : profile.min[k]) << std::setw(8)
                << (empty ? nan : profile.max[k]) << std::setw(8)
                << std::setprecision(0) << profile.count[k] << "\n";
        }
      logger.stream() << table.str();
    }

    /// The cost of the wall coordinates' two solves as numbers (those of
    /// the inspection's own WallCoordinates, the same solves as the
    /// rule-based generator's; scripts/bench reads them).
    void
    write_wall_statistics(const Fibres::WallCoordinates &lv_wall,
                          const double                   n_cells,
                          IO::ResultsFile               &results)
    {
      const Fibres::WallCoordinatesReport r = lv_wall.report();
      results.write_statistics(
        {{"n_cells", "-", n_cells},
         {"degree", "-", static_cast<double>(r.degree)},
         {"n_dofs", "-", static_cast<double>(r.n_dofs)},
         {"transmural_iterations",
          "-",
          static_cast<double>(r.transmural_iterations)},
         {"apicobasal_iterations",
          "-",
          static_cast<double>(r.apicobasal_iterations)},
         {"transmural_direct", "-", r.transmural_direct ? 1.0 : 0.0},
         {"apicobasal_direct", "-", r.apicobasal_direct ? 1.0 : 0.0},
         {"tangled_cells", "-", static_cast<double>(r.n_tangled_cells)},
         {"setup_seconds", "s", r.setup_seconds},
         {"transmural_seconds", "s", r.transmural_seconds},
         {"apicobasal_seconds", "s", r.apicobasal_seconds}});
    }
  } // namespace

  void
  inspect_fibres(const std::string &parameter_file,
                 const MPI_Comm     comm,
                 std::ostream      &out)
  {
    Logger                   logger(comm, out);
    dealii::ParameterHandler prm;
    read_parameter_file(prm, parameter_file);
    const RunParameters run = RunParameters::parse(prm, parameter_file);
    validate_component_parameters(prm, parameter_file);
    const auto geometry =
      Geometry::Parameters::parse(prm, run.parameter_directory);
    const auto fibres = Fibres::Parameters::parse(prm, run.parameter_directory);

    // Hexahedra on p4est, tetrahedra fully distributed.
    const Geometry::DistributedMesh mesh =
      Geometry::create_distributed_mesh(geometry, comm);
    const dealii::parallel::DistributedTriangulationBase<3> &tria = *mesh.tria;
    const Geometry::CellKind                                 kind(tria);
    const double n_cells = static_cast<double>(tria.n_global_active_cells());
    logger.line(IO::code_version() + ": fibres '" + fibres.generator + "' on " +
                std::to_string(tria.n_global_active_cells()) + " " +
                kind.name());
    const Fibres::FibreField field =
      Fibres::create_fibre_field(fibres,
                                 geometry.lv_shape,
                                 tria,
                                 mesh.names,
                                 &logger);
    const WallMeasure wall = wall_measure(fibres, tria, mesh.names, logger);

    const auto    mapping = kind.mapping(tria, run.mapping_degree);
    const Profile profile =
      helix_profile(tria, kind, *mapping, field, wall, comm);
    VertexFields vertex_fields(tria, kind, wall.exists());
    vertex_fields.compute(field, wall, comm);

    IO::ResultsFile results(run.output_directory,
                            parameter_text(prm, parameter_file),
                            comm);
    const double    n_points =
      std::accumulate(profile.count.begin(), profile.count.end(), 0.0);
    results.append_timeseries({{"step", "-", 0.0},
                               {"time", "ms", 0.0},
                               {"n_cells", "-", n_cells},
                               {"n_points", "-", n_points}});
    if (wall.exists())
      write_profile(profile, results, logger);

    dealii::DataOut<3> data_out;
    vertex_fields.attach(data_out);
    data_out.build_patches(*mapping, 1);
    results.write_fields(data_out, 0, 0.0);
    if (wall.lv_wall)
      write_wall_statistics(*wall.lv_wall, n_cells, results);
    logger.line("Wrote " + results.path());
  }
} // namespace systole
