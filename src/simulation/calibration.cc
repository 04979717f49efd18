#include "simulation/calibration.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include "base/errors.h"
#include "base/first_members.h"
#include "base/logger.h"
#include "base/units.h"
#include "geometry/gmsh_export.h"
#include "io/results_file.h"
#include "mechanics/problem.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"
#include "simulation/reference_unloader.h"
#include "simulation/unloading.h"

#include "inverse/adjustable_law.h"
#include "inverse/inflation.h"
#include "inverse/klotz.h"
#include "inverse/least_squares.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <random>
#include <set>
#include <sstream>

namespace systole
{
  namespace
  {
    const std::string section = "Calibration / ";

    std::vector<double>
    parse_numbers(const std::string &text, const std::string &entry)
    {
      std::vector<double> values;
      for (const auto &item : dealii::Utilities::split_string_list(text, ','))
        {
          std::istringstream in(item);
          double             v;
          std::string        rest;
          AssertThrow((in >> v) && !(in >> rest),
                      dealii::ExcMessage(section + entry + ": '" + item +
                                         "' is not a number (give a "
                                         "comma-separated list)."));
          values.push_back(v);
        }
      return values;
    }

    /// One bound per parameter, or one for all.
    std::vector<double>
    parse_bounds(const std::string &text,
                 const std::string &entry,
                 const unsigned int n)
    {
      auto values = parse_numbers(text, entry);
      if (values.size() == 1)
        values.assign(n, values[0]);
      AssertThrow(values.size() == n,
                  dealii::ExcMessage(section + entry + " has " +
                                     std::to_string(values.size()) +
                                     " values for " + std::to_string(n) +
                                     " parameters: give one per parameter "
                                     "or one for all."));
      return values;
    }

    std::string
    fixed(const double v, const int digits)
    {
      std::ostringstream o;
      o << std::fixed << std::setprecision(digits) << v;
      return o.str();
    }

    /// How the fit evaluates and minimizes its residuals.
    void
    declare_solver(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Finite difference step",
        "1e-3",
        Double(1e-8, 0.1),
        "Relative step of the forward differences of the "
        "volumes in the parameters (each value times 1 + step). "
        "Units: -.");
      prm.declare_entry("Pressure step",
                        "2.5",
                        Double(1e-6),
                        "Largest pressure increment of the inflation ramp (cut "
                        "in half when Newton fails, up to Mechanics / Maximum "
                        "step cuts times). Units: mmHg.");
      prm.declare_entry(
        "Reference",
        "given",
        Selection("given|unloaded"),
        "given: the mesh of subsection Geometry is the stress-free reference "
        "of every inflation. unloaded: the mesh is the ventricle imaged at "
        "Unloading / Image pressure (loaded, as a patient's image is): every "
        "evaluation of the fit unloads the image with its parameter values "
        "(Problem = unloading's fixed point with Unloading / Tolerance, "
        "Acceleration and Maximum iterations, started from the last "
        "evaluation's reference) and inflates that reference; the "
        "finite-difference derivatives unload anew for each perturbed value, "
        "so choose Unloading / Tolerance small against Finite difference step "
        "times the displacements (e.g. 1e-4 mm with a step of 1e-2). Fibres / "
        "Generator must be rule-based (recomputed on every reference). Target "
        "= Klotz with Klotz end-diastolic volume = 0 takes the image's cavity "
        "volume (its vertices, trilinear cells), at Klotz end-diastolic "
        "pressure, which must equal Unloading / Image pressure. Writes the "
        "unloaded mesh of the fitted values (Unloading / Mesh file) beside the "
        "results. Units: -.");
      prm.declare_entry(
        "Residual tolerance",
        "0",
        Double(0.0),
        "Stop the fit when the norm of the relative residuals |r| is at most "
        "this (the data are matched; 0: off, TAO's gradient tests and the "
        "stagnation test only). With Reference = unloaded the unloading's "
        "tolerance leaves a noise floor in r (about 1e-6 at Unloading / "
        "Tolerance = 1e-4 mm on the coarse ventricle) below which the line "
        "search fails. Units: -.");
      prm.declare_entry("Maximum iterations",
                        "30",
                        Integer(1),
                        "Iterations of the least-squares solver (PETSc TAO, "
                        "bounded regularized Gauss-Newton; PETSc options with "
                        "the prefix -calibration_ reach it). Units: -.");
    }


    /// What the fit matches: the Target and its data.
    void
    declare_target(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Target",
        "Klotz",
        Selection("Klotz|pressure-volume pairs|synthetic"),
        "What to fit. 'Klotz': the end-diastolic pressure-volume relation of "
        "Klotz et al. 2006 (Am. J. Physiol. 291:H403) through (Klotz "
        "end-diastolic pressure, Klotz end-diastolic volume), at the Target "
        "pressures. 'pressure-volume pairs': the pairs of Pressure-volume "
        "pairs. 'synthetic': the volumes of this model with the entries set to "
        "Synthetic values at the Target pressures, with relative Gaussian "
        "noise of standard deviation Synthetic noise (a round-trip test). The "
        "residuals are relative: V_model / V_target - 1 at each pressure.");
      prm.declare_entry("Pressure-volume pairs",
                        "",
                        Anything(),
                        "Target = pressure-volume pairs: 'p: V, p: V, ...' "
                        "with p in mmHg (> 0) and V in mL (cavity volume). At "
                        "least as many pairs as parameters (one more for the "
                        "covariance). Units: mmHg: mL.");
      prm.declare_entry("Target pressures",
                        "5, 10, 15, 20, 25",
                        Anything(),
                        "Target = Klotz or synthetic: the pressures at which "
                        "the target volumes are taken (> 0, comma-separated). "
                        "Units: mmHg.");
      prm.declare_entry("Klotz end-diastolic pressure",
                        "10",
                        Double(0.0, 100.0),
                        "Target = Klotz: the measured end-diastolic pressure "
                        "EDP_m (> 0 and < 100: the curve's V_0 = V_m (0.6 - "
                        "0.006 EDP_m) must be positive). Units: mmHg.");
      prm.declare_entry(
        "Klotz end-diastolic volume",
        "0",
        Double(0.0),
        "Target = Klotz: the measured end-diastolic volume V_m; 0: the cavity "
        "volume of this model with the parameters of the file at Klotz "
        "end-diastolic pressure (an inflation before the fit). Units: mL.");
      prm.declare_entry("Synthetic values",
                        "",
                        Anything(),
                        "Target = synthetic: the true values of the fitted "
                        "entries (one per parameter, > 0). Units: those of the "
                        "entries (kPa for stiffnesses, - for exponents).");
      prm.declare_entry(
        "Synthetic noise",
        "0",
        Double(0.0, 0.5),
        "Target = synthetic: standard deviation of the relative "
        "Gaussian noise on the synthetic volumes (V (1 + noise "
        "N(0, 1))). Units: -.");
      prm.declare_entry("Noise seed",
                        "42",
                        Integer(0),
                        "Target = synthetic: seed of the noise (std::mt19937). "
                        "Units: -.");
    }

  } // namespace

  void
  CalibrationParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Calibration");
    prm.declare_entry(
      "Parameters",
      "C",
      Anything(),
      "Problem = calibration: the entries of subsection Material / <Passive "
      "law> to fit, 1 to 4, comma-separated (e.g. 'a, a_f' for "
      "Holzapfel-Ogden, 'C' for Guccione). Each is fitted as a positive scale "
      "factor of its value in the file (the initial guess), so stiffnesses "
      "and exponents are fitted alike. Units: -.");
    prm.declare_entry("Lower bounds",
                      "0.1",
                      Anything(),
                      "Lower bounds of the fitted scale factors (fitted value "
                      "/ value in the file), one per parameter or one for "
                      "all; > 0 and <= 1. Units: -.");
    prm.declare_entry("Upper bounds",
                      "10",
                      Anything(),
                      "Upper bounds of the fitted scale factors, one per "
                      "parameter or one for all; >= 1. Units: -.");
    declare_target(prm);
    declare_solver(prm);
    prm.leave_subsection();
  }

  CalibrationParameters
  CalibrationParameters::parse(const dealii::ParameterHandler &prm)
  {
    CalibrationParameters          p;
    const std::vector<std::string> s = {"Calibration"};
    p.parameters =
      dealii::Utilities::split_string_list(prm.get(s, "Parameters"), ',');
    const unsigned int n = p.parameters.size();
    AssertThrow(n >= 1 && n <= 4,
                dealii::ExcMessage(section + "Parameters names " +
                                   std::to_string(n) +
                                   " entries: fit 1 to 4 parameters."));
    AssertThrow(
      std::set<std::string>(p.parameters.begin(), p.parameters.end()).size() ==
        n,
      dealii::ExcMessage(section + "Parameters names an entry twice."));
    p.lower = parse_bounds(prm.get(s, "Lower bounds"), "Lower bounds", n);
    p.upper = parse_bounds(prm.get(s, "Upper bounds"), "Upper bounds", n);
    for (unsigned int i = 0; i < n; ++i)
      AssertThrow(p.lower[i] > 0 && p.lower[i] <= 1 && p.upper[i] >= 1,
                  dealii::ExcMessage(
                    section + "Lower bounds and Upper bounds of " +
                    p.parameters[i] + " (" +
                    dealii::Utilities::to_string(p.lower[i]) + ", " +
                    dealii::Utilities::to_string(p.upper[i]) +
                    ") must satisfy 0 < lower <= 1 <= upper: they bound the "
                    "scale factor of the value in the file, which starts at "
                    "1."));
    p.target = prm.get(s, "Target");
    if (p.target == "pressure-volume pairs")
      {
        for (const auto &item : dealii::Utilities::split_string_list(
               prm.get(s, "Pressure-volume pairs"),
               ','))
          {
            const auto pv = dealii::Utilities::split_string_list(item, ':');
            AssertThrow(pv.size() == 2,
                        dealii::ExcMessage(
                          section + "Pressure-volume pairs: '" + item +
                          "' is not 'p: V' (p in mmHg, V in mL)."));
            const double pressure =
              parse_numbers(pv[0], "Pressure-volume pairs")[0];
            const double volume =
              parse_numbers(pv[1], "Pressure-volume pairs")[0];
            AssertThrow(pressure > 0 && volume > 0,
                        dealii::ExcMessage(section +
                                           "Pressure-volume pairs: '" + item +
                                           "' needs p > 0 mmHg and V > 0 mL."));
            p.pairs.emplace_back(pressure, volume);
          }
        std::sort(p.pairs.begin(), p.pairs.end());
        for (unsigned int i = 1; i < p.pairs.size(); ++i)
          AssertThrow(
            p.pairs[i].first > p.pairs[i - 1].first,
            dealii::ExcMessage(
              section + "Pressure-volume pairs gives two volumes at " +
              dealii::Utilities::to_string(p.pairs[i].first) + " mmHg."));
        AssertThrow(p.pairs.size() >= n,
                    dealii::ExcMessage(
                      section + "Pressure-volume pairs has " +
                      std::to_string(p.pairs.size()) + " pairs for " +
                      std::to_string(n) +
                      " parameters: give at least as many pairs as "
                      "parameters (one more for the covariance)."));
      }
    else
      {
        p.pressures_mmHg =
          parse_numbers(prm.get(s, "Target pressures"), "Target pressures");
        std::sort(p.pressures_mmHg.begin(), p.pressures_mmHg.end());
        AssertThrow(!p.pressures_mmHg.empty() && p.pressures_mmHg[0] > 0 &&
                      std::adjacent_find(p.pressures_mmHg.begin(),
                                         p.pressures_mmHg.end()) ==
                        p.pressures_mmHg.end() &&
                      p.pressures_mmHg.size() >= n,
                    dealii::ExcMessage(
                      section +
                      "Target pressures must be distinct, > 0 mmHg, and at "
                      "least as many as the parameters (one more for the "
                      "covariance)."));
      }
    p.klotz_edp_mmHg = prm.get_double(s, "Klotz end-diastolic pressure");
    p.klotz_edv_mL   = prm.get_double(s, "Klotz end-diastolic volume");
    AssertThrow(p.target != "Klotz" ||
                  (p.klotz_edp_mmHg > 0 && p.klotz_edp_mmHg < 100),
                dealii::ExcMessage(
                  section + "Klotz end-diastolic pressure must be > 0 and < "
                            "100 mmHg (Klotz's V_0 = V_m (0.6 - 0.006 EDP_m) "
                            "is not positive above)."));
    if (p.target == "synthetic")
      {
        p.synthetic_values =
          parse_numbers(prm.get(s, "Synthetic values"), "Synthetic values");
        AssertThrow(p.synthetic_values.size() == n,
                    dealii::ExcMessage(section +
                                       "Synthetic values needs one value per "
                                       "parameter of Calibration / "
                                       "Parameters (" +
                                       std::to_string(n) + ")."));
        for (const double v : p.synthetic_values)
          AssertThrow(v > 0,
                      dealii::ExcMessage(section +
                                         "Synthetic values must be > 0."));
      }
    p.synthetic_noise        = prm.get_double(s, "Synthetic noise");
    p.noise_seed             = prm.get_integer(s, "Noise seed");
    p.finite_difference_step = prm.get_double(s, "Finite difference step");
    p.pressure_step_mmHg     = prm.get_double(s, "Pressure step");
    p.max_iterations         = prm.get_integer(s, "Maximum iterations");
    p.reference              = prm.get(s, "Reference");
    p.residual_tolerance     = prm.get_double(s, "Residual tolerance");
    return p;
  }

  namespace
  {
    /// One calibration run: the targets, the least-squares fit of the
    /// law's entries (through PassiveInflation, and the unloading of the
    /// image for each evaluation with Reference = unloaded) and its output.
    class CalibrationRun
    {
    public:
      explicit CalibrationRun(const RunInputs &in);

      /// Fit, report, write the tables, calibrated.prm and the statistics.
      void
      run();

    private:
      /// The initial values of the fitted entries, checked positive.
      std::vector<double>
      checked_initial_values() const;

      /// The adjustable law of the mechanics (law points to it).
      std::unique_ptr<Inverse::AdjustableLaw>
      make_law();

      /// Subsection Unloading, checked against the targets: with Reference
      /// = unloaded and Target = Klotz the image pressure is the Klotz
      /// pressure.
      UnloadingParameters
      checked_unloading(const dealii::ParameterHandler &prm) const;

      /// The unloader, the image and the given mesh (Reference = unloaded).
      void
      set_up_unloading(const dealii::ParameterHandler &prm);

      /// The inflation of the current mechanics to @p pressures [kPa].
      Inverse::PassiveInflation
      inflation_over(const std::vector<double> &pressures);

      /// The inflation counts over every reference.
      Inverse::InflationCounts
      counts() const;

      /// The same numbers on every rank, bit for bit (TAO runs on each).
      void
      broadcast(std::vector<double> &v) const;

      /// targets.volumes_mL from the target (pairs, the Klotz curve, or
      /// synthetic).
      void
      set_target_volumes();
      void
      set_klotz_targets();
      void
      set_synthetic_targets();

      /// Unload the image with @p values from @p start and inflate the
      /// reference: the volumes [mm^3].
      std::vector<double>
      unload_and_inflate(const std::vector<double>           &values,
                         const std::vector<dealii::Point<3>> &start,
                         UnloadingResult                     &u);

      /// The volumes [mm^3] (and their derivatives) of @p values on the
      /// unloaded reference of each; @p stats: fixed-point iterations,
      /// reference volume [mL], reload error [mm].
      std::vector<double>
      unloaded_volumes(const std::vector<double> &values,
                       std::vector<double>       *dV,
                       std::vector<double>       &stats);

      /// The least-squares residuals (and Jacobian) at scale factors @p x.
      void
      evaluate(const std::vector<double> &x,
               std::vector<double>       &r,
               std::vector<double>       *J);

      /// The evaluation's row of /timeseries and its console line.
      void
      record_evaluation(const std::vector<double> &values,
                        const double               rss,
                        std::vector<double>        reference_stats);

      /// The console report and the calibration/ tables of @p fit.
      void
      report(const Inverse::LeastSquaresResult &fit, const double seconds);

      /// calibrated.prm (and the unloaded mesh): what a later run includes.
      std::string
      write_fragment(const std::vector<double> &fitted,
                     const std::string         &mesh_path) const;

      void
      write_statistics(const unsigned int tao_iterations, const double seconds);

      const RunParameters                  &run_params;
      Logger                               &logger;
      const MPI_Comm                        comm;
      std::chrono::steady_clock::time_point start;
      const CalibrationParameters           cal;
      const unsigned int                    n;
      const bool                            unloaded;
      const UnloadingParameters             up;
      Inverse::LawRebuilder                 rebuilder;
      const std::vector<double>             initial;
      Inverse::AdjustableLaw               *law = nullptr;
      MechanicsModel                        model;
      IO::ResultsFile                       results;

      /// The target pressures (ascending) and volumes.
      struct Targets
      {
        std::vector<double> pressures_mmHg;
        unsigned int        n_pressures = 0;
        std::vector<double> pressures_kPa;
        std::vector<double> volumes_mL;
        /// Target = Klotz: the end-diastolic volume and the curve's V0, V30.
        double klotz_edv = 0, klotz_v0 = 0, klotz_v30 = 0;
      } targets;

      /// Reference = unloaded: the mesh is the image; the unloader moves
      /// the mesh's vertices to the unloaded reference of the current
      /// parameters (and rebuilds model.problem on it: use *model.problem
      /// afresh).
      struct Unloading
      {
        std::unique_ptr<ReferenceUnloader> unloader;
        std::vector<dealii::Point<3>>      image, given;
        double                             image_volume = 0;
        /// The unloadings so far: totals, the last one's reference and
        /// statistics.
        UnloadingResult               total;
        unsigned int                  fixed_point_iterations = 0;
        std::vector<dealii::Point<3>> last_reference;
        std::vector<double>           last_reference_stats;
      } unloading;

      /// One inflation per reference (it holds the mechanics built on it);
      /// the counts of the earlier ones.
      std::unique_ptr<Inverse::PassiveInflation> inflation;
      Inverse::InflationCounts                   earlier;
      unsigned int                               extra_solves = 0;

      std::vector<double> initial_model_mL;
      unsigned int        evaluation = 0;
    };


    CalibrationRun::CalibrationRun(const RunInputs &in)
      : run_params(in.run)
      , logger(in.logger)
      , comm(in.comm)
      , start(std::chrono::steady_clock::now())
      , cal(CalibrationParameters::parse(in.prm))
      , n(cal.parameters.size())
      , unloaded(cal.reference == "unloaded")
      , up(checked_unloading(in.prm))
      , rebuilder(in.prm, cal.parameters, "Calibration / Parameters")
      , initial(checked_initial_values())
      , model(in.prm, in.run, in.logger, in.comm, "", make_law())
      , results(in.run.output_directory, in.parameter_text, in.comm)
    {
      in.logger.line(model.banner(in.run));
      set_up_unloading(in.prm);
      targets.pressures_mmHg = cal.pressures_mmHg;
      if (cal.target == "pressure-volume pairs")
        {
          targets.pressures_mmHg = first_members(cal.pairs);
        }
      targets.n_pressures = targets.pressures_mmHg.size();
      for (const double p : targets.pressures_mmHg)
        targets.pressures_kPa.push_back(Units::mmHg_to_kPa(p));
      inflation = std::make_unique<Inverse::PassiveInflation>(
        inflation_over(targets.pressures_kPa));
      set_target_volumes();
      unloading.last_reference = unloading.image;
    }


    std::vector<double>
    CalibrationRun::checked_initial_values() const
    {
      const std::vector<double> values = rebuilder.initial_values();
      for (unsigned int i = 0; i < n; ++i)
        AssertThrow(values[i] > 0,
                    dealii::ExcMessage(
                      "Calibration / Parameters: Material / " +
                      rebuilder.law_name() + " / " + cal.parameters[i] +
                      " is 0 in the file; a fitted entry is a scale factor "
                      "of its value there, so give it a positive starting "
                      "value."));
      return values;
    }


    std::unique_ptr<Inverse::AdjustableLaw>
    CalibrationRun::make_law()
    {
      auto adjustable =
        std::make_unique<Inverse::AdjustableLaw>(rebuilder.build(initial));
      law = adjustable.get();
      return adjustable;
    }


    UnloadingParameters
    CalibrationRun::checked_unloading(const dealii::ParameterHandler &prm) const
    {
      const UnloadingParameters checked = UnloadingParameters::parse(prm);
      AssertThrow(!unloaded || cal.target != "Klotz" ||
                    std::abs(cal.klotz_edp_mmHg -
                             Units::kPa_to_mmHg(checked.image_pressure)) <=
                      1e-9 * cal.klotz_edp_mmHg,
                  dealii::ExcMessage(
                    section +
                    "Reference = unloaded with Target = Klotz: the image is "
                    "the end-diastolic geometry, so Calibration / Klotz "
                    "end-diastolic pressure (" +
                    fixed(cal.klotz_edp_mmHg, 3) +
                    " mmHg) must equal Unloading / Image pressure (" +
                    fixed(Units::kPa_to_mmHg(checked.image_pressure), 3) +
                    " mmHg)."));
      return checked;
    }


    void
    CalibrationRun::set_up_unloading(const dealii::ParameterHandler &prm)
    {
      if (!unloaded)
        return;
      unloading.unloader = std::make_unique<ReferenceUnloader>(
        model,
        run_params,
        Fibres::Parameters::parse(prm, run_params.parameter_directory),
        logger,
        comm);
      unloading.image        = unloading.unloader->vertices();
      unloading.given        = unloading.image;
      unloading.image_volume = model.problem->cavity_volume();
    }


    Inverse::PassiveInflation
    CalibrationRun::inflation_over(const std::vector<double> &pressures)
    {
      return Inverse::PassiveInflation(*model.problem,
                                       *law,
                                       rebuilder,
                                       pressures,
                                       Units::mmHg_to_kPa(
                                         cal.pressure_step_mmHg),
                                       model.params.max_step_cuts,
                                       logger);
    }


    Inverse::InflationCounts
    CalibrationRun::counts() const
    {
      Inverse::InflationCounts c = inflation->counts();
      c.inflations += earlier.inflations;
      c.load_steps += earlier.load_steps;
      c.step_cuts += earlier.step_cuts;
      c.forward_solves += earlier.forward_solves;
      c.perturbed_solves += earlier.perturbed_solves;
      c.newton_iterations += earlier.newton_iterations;
      c.chord_iterations += earlier.chord_iterations;
      return c;
    }


    void
    CalibrationRun::broadcast(std::vector<double> &v) const
    {
      MPI_Bcast(v.data(), v.size(), MPI_DOUBLE, 0, comm);
    }


    void
    CalibrationRun::set_target_volumes()
    {
      targets.volumes_mL.assign(targets.n_pressures, 0.0);
      targets.klotz_edv = cal.klotz_edv_mL;
      if (cal.target == "pressure-volume pairs")
        for (unsigned int j = 0; j < targets.n_pressures; ++j)
          targets.volumes_mL[j] = cal.pairs[j].second;
      else if (cal.target == "Klotz")
        set_klotz_targets();
      else
        set_synthetic_targets();
    }


    void
    CalibrationRun::set_klotz_targets()
    {
      if (targets.klotz_edv == 0 && unloaded)
        {
          targets.klotz_edv = Units::mm3_to_mL(unloading.image_volume);
          logger.line("Klotz: the image's cavity volume at " +
                      fixed(cal.klotz_edp_mmHg, 2) +
                      " mmHg (its vertices, trilinear cells): " +
                      fixed(targets.klotz_edv, 3) + " mL");
        }
      else if (targets.klotz_edv == 0)
        {
          auto own = inflation_over({Units::mmHg_to_kPa(cal.klotz_edp_mmHg)});
          std::vector<double> v = own.volumes(initial, nullptr, 0.0);
          broadcast(v);
          targets.klotz_edv = Units::mm3_to_mL(v[0]);
          extra_solves += own.counts().forward_solves;
          logger.line("Klotz: the model's own volume at " +
                      fixed(cal.klotz_edp_mmHg, 2) +
                      " mmHg with the "
                      "parameters of the file: " +
                      fixed(targets.klotz_edv, 3) + " mL");
        }
      const Inverse::KlotzCurve curve(cal.klotz_edp_mmHg, targets.klotz_edv);
      targets.klotz_v0  = curve.v0_mL();
      targets.klotz_v30 = curve.v30_mL();
      for (unsigned int j = 0; j < targets.n_pressures; ++j)
        targets.volumes_mL[j] = curve.volume_mL(targets.pressures_mmHg[j]);
      logger.line("Klotz EDPVR through (" + fixed(cal.klotz_edp_mmHg, 2) +
                  " mmHg, " + fixed(targets.klotz_edv, 3) +
                  " mL): V0 = " + fixed(targets.klotz_v0, 3) +
                  " mL, V30 = " + fixed(targets.klotz_v30, 3) + " mL");
    }


    void
    CalibrationRun::set_synthetic_targets()
    {
      auto                truth = inflation_over(targets.pressures_kPa);
      std::vector<double> v = truth.volumes(cal.synthetic_values, nullptr, 0.0);
      broadcast(v);
      extra_solves += truth.counts().forward_solves;
      std::mt19937                     rng(cal.noise_seed);
      std::normal_distribution<double> normal(0.0, 1.0);
      for (unsigned int j = 0; j < targets.n_pressures; ++j)
        targets.volumes_mL[j] =
          Units::mm3_to_mL(v[j]) * (1 + cal.synthetic_noise * normal(rng));
      if (!unloaded)
        return;
      // The round trip: the given mesh is the true reference; the image is
      // its inflation with the true values to the image pressure (its
      // vertices), from which the calibration starts.
      law->set(rebuilder.build(cal.synthetic_values));
      unloading.unloader->set_vertices(unloading.given);
      const auto r = unloading.unloader->inflate(up.image_pressure);
      extra_solves += r.steps;
      unloading.image_volume = model.problem->cavity_volume();
      const auto u           = unloading.unloader->displacements();
      for (unsigned int i = 0; i < unloading.image.size(); ++i)
        unloading.image[i] = unloading.given[i] + u[i];
      law->set(rebuilder.build(initial));
      logger.line("Synthetic image: the true reference inflated to " +
                  fixed(Units::kPa_to_mmHg(up.image_pressure), 2) +
                  " mmHg holds " +
                  fixed(Units::mm3_to_mL(unloading.image_volume), 3) + " mL");
    }


    // Reference = unloaded: every evaluation unloads the image with its
    // values (the fixed point started from the reference of the last
    // unperturbed evaluation) and inflates that reference; the derivatives
    // difference whole unload-and-inflate evaluations, the reference
    // unloaded anew for each perturbed value (started from the unperturbed
    // one's).
    std::vector<double>
    CalibrationRun::unload_and_inflate(
      const std::vector<double>           &values,
      const std::vector<dealii::Point<3>> &start,
      UnloadingResult                     &u)
    {
      law->set(rebuilder.build(values));
      unloading.unloader->set_vertices(start);
      const auto log_iteration = [&](const UnloadingIteration &it) {
        logger.detail() << "    unloading iteration " << it.iteration
                        << ": reference "
                        << Units::mm3_to_mL(it.reference_volume)
                        << " mL, reload error " << it.reload_error << " mm"
                        << std::endl;
      };
      const std::vector<dealii::Point<3>> *truth =
        cal.target == "synthetic" ? &unloading.given : nullptr;
      u = unloading.unloader->unload(unloading.image, up, truth, log_iteration);
      unloading.fixed_point_iterations += u.iterations;
      unloading.total.forward_solves += u.forward_solves;
      unloading.total.totals += u.totals;
      earlier   = counts();
      inflation = std::make_unique<Inverse::PassiveInflation>(
        inflation_over(targets.pressures_kPa));
      auto V = inflation->volumes(values, nullptr, 0.0);
      broadcast(V);
      return V;
    }


    std::vector<double>
    CalibrationRun::unloaded_volumes(const std::vector<double> &values,
                                     std::vector<double>       *dV,
                                     std::vector<double>       &stats)
    {
      UnloadingResult u;
      const auto V = unload_and_inflate(values, unloading.last_reference, u);
      const std::vector<dealii::Point<3>> reference =
        unloading.unloader->vertices();
      unloading.last_reference       = reference;
      unloading.total.last           = u.last;
      stats                          = {static_cast<double>(u.iterations),
                                        Units::mm3_to_mL(u.last.reference_volume),
                                        u.last.reload_error};
      unloading.last_reference_stats = stats;
      if (!dV)
        return V;
      const double h = cal.finite_difference_step;
      dV->assign(targets.n_pressures * n, 0.0);
      for (unsigned int i = 0; i < n; ++i)
        {
          std::vector<double> perturbed = values;
          perturbed[i] *= 1 + h;
          UnloadingResult up_i;
          const auto      Vi = unload_and_inflate(perturbed, reference, up_i);
          for (unsigned int j = 0; j < targets.n_pressures; ++j)
            (*dV)[j * n + i] = (Vi[j] - V[j]) / (h * values[i]);
        }
      // Back to the unperturbed reference (the next evaluation starts
      // there; the mechanics is rebuilt then).
      law->set(rebuilder.build(values));
      return V;
    }


    void
    CalibrationRun::evaluate(const std::vector<double> &x,
                             std::vector<double>       &r,
                             std::vector<double>       *J)
    {
      std::vector<double> values(n);
      for (unsigned int i = 0; i < n; ++i)
        values[i] = x[i] * initial[i];
      std::vector<double> dV;
      std::vector<double> V;
      bool                failed = false;
      std::vector<double> reference_stats;
      try
        {
          if (unloaded)
            V = unloaded_volumes(values, J ? &dV : nullptr, reference_stats);
          else
            V = inflation->volumes(values,
                                   J ? &dV : nullptr,
                                   cal.finite_difference_step);
        }
      catch (const dealii::ExceptionBase &e)
        {
          // A trial point of the line search where the inflation fails
          // (collectively) counts as a very bad point (every relative
          // residual 1), so TAO steps back; the first point must work.
          if (evaluation == 0)
            throw;
          failed = true;
          logger.line("  Evaluation " + std::to_string(evaluation) +
                      ": the inflation failed (" + one_line_message(e) +
                      "); residuals set to 1");
        }
      if (!failed)
        {
          broadcast(V);
          if (J)
            broadcast(dV);
        }
      double rss = 0;
      for (unsigned int j = 0; j < targets.n_pressures; ++j)
        {
          const double target = Units::mL_to_mm3(targets.volumes_mL[j]);
          r[j]                = failed ? 1.0 : V[j] / target - 1;
          rss += r[j] * r[j];
          if (J)
            for (unsigned int i = 0; i < n; ++i)
              (*J)[j * n + i] =
                failed ? 0.0 : dV[j * n + i] * initial[i] / target;
        }
      if (initial_model_mL.empty() && !failed)
        for (const double v : V)
          initial_model_mL.push_back(Units::mm3_to_mL(v));
      record_evaluation(values, rss, reference_stats);
      ++evaluation;
    }


    void
    CalibrationRun::record_evaluation(const std::vector<double> &values,
                                      const double               rss,
                                      std::vector<double> reference_stats)
    {
      std::vector<IO::Column> row = {
        {"evaluation", "-", static_cast<double>(evaluation)}};
      std::ostringstream line;
      line << "  Evaluation " << evaluation << ":";
      for (unsigned int i = 0; i < n; ++i)
        {
          row.push_back({cal.parameters[i], "entry units", values[i]});
          line << " " << cal.parameters[i] << " = " << std::setprecision(6)
               << values[i];
        }
      row.push_back({"residual_norm", "-", std::sqrt(rss)});
      row.push_back(
        {"forward_solves",
         "-",
         static_cast<double>(counts().forward_solves + extra_solves)});
      if (unloaded)
        {
          if (reference_stats.empty())
            reference_stats.assign(3, std::nan(""));
          row.push_back({"fixed_point_iterations", "-", reference_stats[0]});
          row.push_back({"reference_volume_mL", "mL", reference_stats[1]});
          row.push_back({"reload_max_error_mm", "mm", reference_stats[2]});
          line << "  (unloaded in " << reference_stats[0]
               << " iterations: " << fixed(reference_stats[1], 3) << " mL)";
        }
      line << "  |r| = " << std::scientific << std::setprecision(4)
           << std::sqrt(rss);
      results.append_timeseries(row);
      logger.line(line.str());
    }


    void
    CalibrationRun::run()
    {
      // The least-squares problem in the scale factors x (value = x
      // initial).
      Inverse::LeastSquaresProblem ls;
      ls.n_residuals = targets.n_pressures;
      ls.initial.assign(n, 1.0);
      ls.lower    = cal.lower;
      ls.upper    = cal.upper;
      ls.evaluate = [this](const std::vector<double> &x,
                           std::vector<double>       &r,
                           std::vector<double>       *J) { evaluate(x, r, J); };
      Inverse::LeastSquaresSettings settings;
      settings.max_iterations     = cal.max_iterations;
      settings.residual_tolerance = cal.residual_tolerance;

      const auto fit = Inverse::solve_least_squares(ls, settings);
      if (unloaded)
        {
          // The mechanics on the unloaded reference of the fitted values.
          std::vector<double> values(n);
          for (unsigned int i = 0; i < n; ++i)
            values[i] = fit.x[i] * initial[i];
          unloaded_volumes(values, nullptr, unloading.last_reference_stats);
        }
      const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
      report(fit, seconds);
      write_statistics(fit.iterations, seconds);
    }


    void
    CalibrationRun::report(const Inverse::LeastSquaresResult &fit,
                           const double                       seconds)
    {
      const unsigned int tao_iterations = fit.iterations;
      // Report: the parameters (values in the entries' units) and the
      // EDPVR.
      std::vector<double> fitted(n), sd(n), lo(n), hi(n), lower(n), upper(n),
        at_bound(n);
      for (unsigned int i = 0; i < n; ++i)
        {
          fitted[i]   = fit.x[i] * initial[i];
          sd[i]       = fit.standard_deviation[i] * initial[i];
          lo[i]       = fit.lower_95[i] * initial[i];
          hi[i]       = fit.upper_95[i] * initial[i];
          lower[i]    = cal.lower[i] * initial[i];
          upper[i]    = cal.upper[i] * initial[i];
          at_bound[i] = fit.at_bound[i] ? 1.0 : 0.0;
        }
      std::vector<double> fitted_mL(targets.n_pressures),
        residuals = fit.residual;
      for (unsigned int j = 0; j < targets.n_pressures; ++j)
        fitted_mL[j] = (1 + fit.residual[j]) * targets.volumes_mL[j];
      if (initial_model_mL.empty())
        initial_model_mL = fitted_mL;

      std::ostringstream o;
      o << "Calibration of Material / " << rebuilder.law_name() << " ("
        << fit.reason << " after " << tao_iterations << " TAO iterations, "
        << evaluation << " inflations, "
        << counts().forward_solves + extra_solves << " forward solves";
      if (unloaded)
        o << ", " << unloading.fixed_point_iterations
          << " fixed-point iterations of the unloading in "
          << unloading.total.forward_solves << " unloading inflations";
      o << ", " << fixed(seconds, 1) << " s):\n"
        << "  parameter      initial       fitted    std. dev.   95 % "
           "interval\n";
      for (unsigned int i = 0; i < n; ++i)
        o << "  " << std::left << std::setw(8) << cal.parameters[i]
          << std::right << std::setprecision(6) << std::setw(13) << initial[i]
          << std::setw(13) << fitted[i] << std::setw(13) << sd[i] << "   ["
          << lo[i] << ", " << hi[i] << "]"
          << (fit.at_bound[i] ? " at a bound" : "") << "\n";
      o << "  relative residual norm " << std::scientific
        << std::setprecision(4) << fit.residual_norm
        << ", sigma^2 = " << fit.sigma2 << " (" << targets.n_pressures - n
        << " degrees of freedom)\n"
        << std::fixed
        << "  p [mmHg]   target [mL]   fitted [mL]   initial [mL]   error [%]";
      for (unsigned int j = 0; j < targets.n_pressures; ++j)
        o << "\n  " << std::setw(8) << std::setprecision(2)
          << targets.pressures_mmHg[j] << std::setw(14) << std::setprecision(3)
          << targets.volumes_mL[j] << std::setw(14) << fitted_mL[j]
          << std::setw(15) << initial_model_mL[j] << std::setw(12)
          << std::setprecision(3) << 100 * fit.residual[j];
      logger.line(o.str());

      results.write_table("calibration/parameters",
                          {{"name", "", {}, cal.parameters},
                           {"initial", "entry units", initial, {}},
                           {"fitted", "entry units", fitted, {}},
                           {"standard_deviation", "entry units", sd, {}},
                           {"lower_95", "entry units", lo, {}},
                           {"upper_95", "entry units", hi, {}},
                           {"scale_factor", "-", fit.x, {}},
                           {"lower_bound", "entry units", lower, {}},
                           {"upper_bound", "entry units", upper, {}},
                           {"at_bound", "-", at_bound, {}}});
      results.write_table(
        "calibration/edpvr",
        {{"pressure_mmHg", "mmHg", targets.pressures_mmHg, {}},
         {"volume_mL", "mL", fitted_mL, {}},
         {"target_volume_mL", "mL", targets.volumes_mL, {}},
         {"initial_volume_mL", "mL", initial_model_mL, {}},
         {"relative_residual", "-", residuals, {}}});
      std::vector<double> covariance(n * n);
      for (unsigned int a = 0; a < n; ++a)
        for (unsigned int b = 0; b < n; ++b)
          covariance[a * n + b] =
            fit.covariance[a * n + b] * initial[a] * initial[b];
      std::vector<IO::TableColumn> fit_columns = {
        {"target", "", {}, {cal.target}},
        {"residuals", "", {}, {"relative: V_model / V_target - 1"}},
        {"reason", "", {}, {fit.reason}},
        {"converged", "-", {fit.converged ? 1.0 : 0.0}, {}},
        {"residual_norm", "-", {fit.residual_norm}, {}},
        {"sigma2", "-", {fit.sigma2}, {}},
        {"degrees_of_freedom",
         "-",
         {static_cast<double>(targets.n_pressures - n)},
         {}},
        {"t_quantile", "-", {fit.t_quantile}, {}},
        {"tao_iterations", "-", {static_cast<double>(tao_iterations)}, {}},
        {"evaluations", "-", {static_cast<double>(evaluation)}, {}},
        {"reference", "", {}, {cal.reference}},
        {"covariance", "entry units^2", covariance, {}}};
      if (cal.target == "Klotz")
        fit_columns.insert(
          fit_columns.end(),
          {{"klotz_edp_mmHg", "mmHg", {cal.klotz_edp_mmHg}, {}},
           {"klotz_edv_mL", "mL", {targets.klotz_edv}, {}},
           {"klotz_v0_mL", "mL", {targets.klotz_v0}, {}},
           {"klotz_v30_mL", "mL", {targets.klotz_v30}, {}}});
      results.write_table("calibration/fit", fit_columns);

      // Reference = unloaded: the unloaded mesh of the fitted values.
      std::string mesh_path;
      if (unloaded)
        {
          mesh_path = run_params.output_directory + "/" + up.mesh_file;
          Geometry::write_gmsh(model.tria, model.names, mesh_path);
        }
      const std::string fragment = write_fragment(fitted, mesh_path);
      logger.line("Wrote " + results.path() + ", " + fragment +
                  (unloaded ? " and " + mesh_path : ""));
    }


    std::string
    CalibrationRun::write_fragment(const std::vector<double> &fitted,
                                   const std::string         &mesh_path) const
    {
      const std::string fragment =
        run_params.output_directory + "/calibrated.prm";
      if (dealii::Utilities::MPI::this_mpi_process(comm) != 0)
        return fragment;
      std::ofstream out(fragment);
      out << "# Written by Problem = calibration (" << run_params.run_name
          << "): the fitted entries of Material / " << rebuilder.law_name()
          << (unloaded ? " and the unloaded reference mesh" : "")
          << ".\n# A parameter file starts from them with the line\n"
          << "#   include <path of this file>\n"
          << "# after its own entries (deal.II's ParameterHandler: the "
             "path is taken from the\n# current directory; the last "
             "value of an entry wins). The other entries of the law\n"
          << "# must be those of the calibration's file.\n";
      if (unloaded)
        out << "subsection Geometry\n  set Type = gmsh\n"
            << "  subsection Gmsh\n    set Mesh file = "
            << std::filesystem::absolute(mesh_path).lexically_normal().string()
            << "\n  end\nend\n";
      out << "subsection Material\n  set Passive law = " << rebuilder.law_name()
          << "\n  subsection " << rebuilder.law_name() << "\n";
      for (unsigned int i = 0; i < n; ++i)
        out << "    set " << cal.parameters[i] << " = " << std::setprecision(12)
            << fitted[i] << "\n";
      out << "  end\nend\n";
      AssertThrow(out.good(),
                  dealii::ExcMessage("Calibration: cannot write " + fragment +
                                     "."));
      return fragment;
    }


    void
    CalibrationRun::write_statistics(const unsigned int tao_iterations,
                                     const double       seconds)
    {
      std::vector<std::pair<std::string, std::string>> texts;
      auto       statistics = model.statistics(texts);
      const auto c          = counts();
      statistics.insert(
        statistics.end(),
        {{"forward_solves",
          "-",
          static_cast<double>(c.forward_solves + extra_solves)},
         {"perturbed_solves", "-", static_cast<double>(c.perturbed_solves)},
         {"inflations", "-", static_cast<double>(c.inflations)},
         {"load_steps", "-", static_cast<double>(c.load_steps)},
         {"step_cuts", "-", static_cast<double>(c.step_cuts)},
         {"newton_iterations", "-", static_cast<double>(c.newton_iterations)},
         {"chord_iterations", "-", static_cast<double>(c.chord_iterations)},
         {"tao_iterations", "-", static_cast<double>(tao_iterations)},
         {"calibration_seconds", "s", seconds}});
      if (unloaded)
        {
          unloading.unloader->add_earlier_timings(statistics);
          statistics.insert(
            statistics.end(),
            {{"fixed_point_iterations",
              "-",
              static_cast<double>(unloading.fixed_point_iterations)},
             {"unloading_inflations",
              "-",
              static_cast<double>(unloading.total.forward_solves)},
             {"unloading_load_steps",
              "-",
              static_cast<double>(unloading.total.totals.steps)},
             {"unloading_newton_iterations",
              "-",
              static_cast<double>(unloading.total.totals.newton)},
             {"reload_max_error_mm", "mm", unloading.total.last.reload_error},
             {"unloaded_volume_mL",
              "mL",
              Units::mm3_to_mL(unloading.total.last.reference_volume)},
             {"image_volume_mL",
              "mL",
              Units::mm3_to_mL(unloading.image_volume)}});
          if (cal.target == "synthetic")
            statistics.push_back({"reference_max_error_mm",
                                  "mm",
                                  unloading.total.last.reference_error});
        }
      results.write_statistics(statistics, texts);
    }
  } // namespace


  void
  run_calibration_problem(const RunInputs &in)
  {
    // Hundreds of Newton solves: their histories only on request.
    in.logger.set_details(in.run.solver_log == "on");
    CalibrationRun(in).run();
  }
} // namespace systole
