#include <deal.II/base/parameter_handler.h>

#include "electrophysiology/single_cell.h"
#include "simulation/calibration.h"
#include "simulation/cell_run.h"
#include "simulation/circulation_run.h"
#include "simulation/elastodynamics.h"
#include "simulation/electrophysiology_run.h"
#include "simulation/heartbeat.h"
#include "simulation/kinematics.h"
#include "simulation/problem_type.h"
#include "simulation/quasi_static.h"
#include "simulation/unloading.h"

#include "inverse/adjustable_law.h"

namespace systole
{
  namespace
  {
    using RunFunction   = void (*)(const RunInputs &);
    using ParseFunction = void (*)(const dealii::ParameterHandler &);

    /// A problem type made of a run function and the parse of its own
    /// subsections.
    class FunctionProblem : public ProblemType
    {
    public:
      FunctionProblem(const RunFunction run, const ParseFunction parse)
        : run_function(run)
        , parse_function(parse)
      {}

      void
      parse_parameters(const dealii::ParameterHandler &prm) const override
      {
        if (parse_function != nullptr)
          parse_function(prm);
      }

      void
      run(const RunInputs &in) const override
      {
        run_function(in);
      }

    private:
      RunFunction   run_function;
      ParseFunction parse_function;
    };

    /// The builder of a table line.
    std::function<std::unique_ptr<ProblemType>()>
    problem(const RunFunction run, const ParseFunction parse = nullptr)
    {
      return [run, parse]() -> std::unique_ptr<ProblemType> {
        return std::make_unique<FunctionProblem>(run, parse);
      };
    }

    void
    parse_kinematics(const dealii::ParameterHandler &prm)
    {
      KinematicsParameters::parse(prm);
    }

    void
    parse_unloading(const dealii::ParameterHandler &prm)
    {
      UnloadingParameters::parse(prm);
    }

    void
    parse_calibration(const dealii::ParameterHandler &prm)
    {
      UnloadingParameters::parse(prm);
      const auto calibration = CalibrationParameters::parse(prm);
      // The names of the fitted parameters are checked now, not at the first
      // evaluation.
      const Inverse::LawRebuilder check(prm,
                                        calibration.parameters,
                                        "Calibration / Parameters");
    }

    void
    parse_pacing(const dealii::ParameterHandler &prm)
    {
      Electrophysiology::SingleCell::Pacing::parse(prm);
    }
  } // namespace

  ProblemTypeRegistry &
  problem_types()
  {
    static ProblemTypeRegistry registry(
      "Problem",
      {{"cavity volume",
        "build the mesh and follow the cavity volume under a prescribed "
        "uniform stretch about the base centre (subsection Kinematics), a "
        "check of geometry, volume and output.",
        &KinematicsParameters::declare,
        problem(&run_cavity_volume_problem, &parse_kinematics)},
       {"mechanics",
        "quasi-static finite-strain mechanics, the pressure and active "
        "tension ramped in load steps (subsections Material, Mechanics).",
        nullptr,
        problem(&run_quasi_static_problem)},
       {"elastodynamics",
        "the same mechanics with inertia (Mechanics / Density), Kelvin-Voigt "
        "viscosity, Rayleigh damping and spring-dashpot supports, integrated "
        "in time by the generalized-alpha method from rest, from Time / "
        "Start time to End time in steps of Time / Time step, under the "
        "follower pressure and the fibre active stress of subsection "
        "Elastodynamics (Mechanics / Pressure and Active tension are not "
        "used); time series of the loads, cavity volume, tracked points and "
        "energies.",
        &declare_elastodynamics_parameters,
        problem(&run_elastodynamics_problem,
                &validate_elastodynamics_parameters)},
       {"heartbeat",
        "the beating ventricle coupled to a Windkessel afterload through the "
        "four-phase cardiac cycle (subsections Circulation, Active tension, "
        "Material, Mechanics).",
        nullptr,
        problem(&run_heartbeat_problem)},
       {"electrophysiology",
        "the monodomain model alone, activation times and their summary "
        "(subsections Electrophysiology, Fibres).",
        nullptr,
        problem(&run_electrophysiology_problem)},
       {"circulation",
        "the 0D circulation model of Circulation / Model alone, with "
        "elastance ventricles, for Circulation / Number of beats beats; a "
        "time-series row every Time / Time step (subsection Circulation).",
        nullptr,
        problem(&run_circulation_problem)},
       {"cell",
        "one cell of Electrophysiology / Ionic model, paced as subsection "
        "Cell says and integrated with the time step and method of "
        "subsection Electrophysiology; the potential and calcium every Time "
        "/ Time step and the resting and peak potential, APD90 and peak "
        "calcium of every beat.",
        &Electrophysiology::SingleCell::Pacing::declare,
        problem(&run_cell_problem, &parse_pacing)},
       {"unloading",
        "the stress-free reference of the geometry imaged at Unloading / "
        "Image pressure (backward displacement fixed point; writes the "
        "unloaded gmsh mesh; subsections Unloading, Material, Mechanics).",
        &UnloadingParameters::declare,
        problem(&run_unloading_problem, &parse_unloading)},
       {"calibration",
        "fit passive parameters of the Material to an end-diastolic "
        "pressure-volume relation (pairs, Klotz's EDPVR, or synthetic data) "
        "by bounded least squares, each evaluation a pressure inflation "
        "(subsections Calibration, Material, Mechanics).",
        &CalibrationParameters::declare,
        problem(&run_calibration_problem, &parse_calibration)}});
    return registry;
  }
} // namespace systole
