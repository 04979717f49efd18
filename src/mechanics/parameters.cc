#include "mechanics/parameters.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/utilities.h>

#include <algorithm>

namespace systole::Mechanics
{
  namespace
  {
    std::vector<std::string>
    names(const std::string &text)
    {
      return dealii::Utilities::split_string_list(text, ',');
    }

    std::vector<TrackedPoint>
    parse_points(const std::string &text)
    {
      std::vector<TrackedPoint> points;
      for (const auto &item : dealii::Utilities::split_string_list(text, ';'))
        {
          const auto colon = item.find(':');
          AssertThrow(colon != std::string::npos,
                      dealii::ExcMessage(
                        "Mechanics / Tracked points: '" + item +
                        "' is not of the form 'name: x, y, z'."));
          TrackedPoint p;
          p.name = dealii::Utilities::trim(item.substr(0, colon));
          const auto xyz =
            dealii::Utilities::split_string_list(item.substr(colon + 1), ',');
          AssertThrow(!p.name.empty() && xyz.size() == 3,
                      dealii::ExcMessage(
                        "Mechanics / Tracked points: '" + item +
                        "' is not of the form 'name: x, y, z'."));
          for (unsigned int d = 0; d < 3; ++d)
            p.position[d] = dealii::Utilities::string_to_double(xyz[d]);
          points.push_back(p);
        }
      return points;
    }

    /// The options after 'type, alpha, beta' of a support: 'taper h0 s_base'
    /// and 'end-diastole [release time]', each at most once; false if one is
    /// not valid.
    bool
    parse_support_options(const std::vector<std::string> &options,
                          RobinSupport                   &s)
    {
      bool tapered = false;
      for (const auto &option : options)
        {
          const auto words =
            dealii::Utilities::break_text_into_lines(option, 1);
          if ((words.size() == 1 || words.size() == 2) &&
              words[0] == "end-diastole" && !s.from_end_diastole)
            {
              s.from_end_diastole = true;
              if (words.size() == 2)
                s.release_time = dealii::Utilities::string_to_double(words[1]);
              if (!(s.release_time >= 0 && s.release_time < 1e6))
                return false;
            }
          else if (words.size() == 3 && words[0] == "taper" && !tapered)
            {
              tapered       = true;
              s.taper_start = dealii::Utilities::string_to_double(words[1]);
              s.base_scale  = dealii::Utilities::string_to_double(words[2]);
              if (!(s.taper_start >= 0 && s.taper_start < 1 &&
                    s.base_scale >= 0 && s.base_scale <= 1))
                return false;
            }
          else
            return false;
        }
      return true;
    }

    /// One item 'part: type, alpha, beta[, options]' of Robin supports.
    RobinSupport
    parse_support(const std::string &item, const std::string &form)
    {
      const auto message = [&item, &form]() {
        return dealii::ExcMessage("Mechanics / Robin supports: '" + item +
                                  form);
      };
      const auto colon = item.find(':');
      AssertThrow(colon != std::string::npos, message());
      RobinSupport s;
      s.boundary = dealii::Utilities::trim(item.substr(0, colon));
      const auto values =
        dealii::Utilities::split_string_list(item.substr(colon + 1), ',');
      const auto type =
        values.empty() ? std::vector<std::string>()
                       : dealii::Utilities::break_text_into_lines(values[0], 1);
      AssertThrow(!s.boundary.empty() && values.size() >= 3 &&
                    values.size() <= 5 &&
                    ((type.size() == 1 &&
                      (type[0] == "normal" || type[0] == "tangential")) ||
                     ((type.size() == 1 || type.size() == 2) &&
                      type[0] == "full")),
                  message());
      s.normal_only     = type[0] == "normal";
      s.tangential_only = type[0] == "tangential";
      bool valid        = true;
      try
        {
          if (type.size() == 2)
            {
              s.normal_fraction = dealii::Utilities::string_to_double(type[1]);
              valid             = s.normal_fraction >= 0;
            }
          s.stiffness = dealii::Utilities::string_to_double(values[1]);
          s.damping   = dealii::Utilities::string_to_double(values[2]);
          valid       = valid &&
                  parse_support_options({values.begin() + 3, values.end()}, s);
        }
      catch (...)
        {
          valid = false;
        }
      AssertThrow(valid, message());
      AssertThrow(
        s.stiffness >= 0 && s.damping >= 0 && s.stiffness + s.damping > 0,
        dealii::ExcMessage("Mechanics / Robin supports: '" + item +
                           "': the stiffness and the damping must not be "
                           "negative, and not both zero."));
      return s;
    }

    std::vector<RobinSupport>
    parse_supports(const std::string &text)
    {
      const std::string form =
        "' is not of the form 'part: normal|tangential|full [r], stiffness "
        "[kPa/mm], damping [kPa ms/mm]' followed by the options ', taper h0 "
        "s_base' and ', end-diastole [release time, ms]' (r >= 0, 0 <= h0 < "
        "1, 0 <= s_base <= 1, release time >= 0).";
      std::vector<RobinSupport> supports;
      for (const auto &item : dealii::Utilities::split_string_list(text, ';'))
        supports.push_back(parse_support(item, form));
      // (BoundaryConditions holds one rest position for all of them.)
      const auto referred =
        std::find_if(supports.begin(), supports.end(), [](const auto &s) {
          return s.from_end_diastole;
        });
      for (const auto &s : supports)
        AssertThrow(!s.from_end_diastole ||
                      s.release_time == referred->release_time,
                    dealii::ExcMessage(
                      "Mechanics / Robin supports: the supports referred to "
                      "end-diastole have different release times "
                      "('end-diastole T'): give them the same T."));
      return supports;
    }

    /// The boundary conditions: fixed, sliding, pressure and Robin parts.
    void
    declare_boundaries(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Fixed boundaries",
        "base",
        Anything(),
        "Comma-separated boundary parts on which the displacement "
        "is zero in all directions (e.g. base, x_min). Units: -.");
      prm.declare_entry("Sliding boundaries",
                        "",
                        Anything(),
                        "Comma-separated flat boundary parts on which only the "
                        "normal displacement is zero (a base free to slide in "
                        "its plane). Units: -.");
      prm.declare_entry(
        "Pressure boundary",
        "endocardium",
        Anything(),
        "Comma-separated boundary parts that carry a follower pressure each (it "
        "acts along the deformed normal on the deformed area); empty for none. "
        "When the mesh has a boundary part named base, every part listed is a "
        "cavity closed by the base plane (e.g. endocardium, or the two "
        "endocardia of a biventricular mesh): it has a volume, its pressure may "
        "be the multiplier of a volume constraint, and the tangent is "
        "symmetric. Each part carries its own pressure; the mechanics problem "
        "applies Pressure to all of them. Units: -.");
      prm.declare_entry(
        "Pressure",
        "0",
        Double(),
        "Pressure at the end of the load ramp, pushing into the "
        "body, the same on every part of Pressure boundary "
        "(cavity pressure on the endocardium). Units: kPa "
        "(1 mmHg = 0.133322 kPa).");
      prm.declare_entry("Robin boundaries",
                        "",
                        Anything(),
                        "Comma-separated boundary parts held by linear springs "
                        "(e.g. epicardium). Units: -.");
      prm.declare_entry("Robin stiffness",
                        "0",
                        Double(0.0),
                        "Spring stiffness per reference area of the Robin "
                        "boundaries. Units: kPa/mm.");
      prm.declare_entry("Robin type",
                        "normal",
                        Selection("normal|full"),
                        "normal: springs resist the normal displacement only; "
                        "full: all components. Units: -.");
      prm.declare_entry(
        "Robin damping",
        "0",
        Double(0.0),
        "Dashpot coefficient per reference area of the Robin boundaries (the "
        "traction -beta v, normal or full as Robin type says), in time "
        "integrations with inertia (Problem = elastodynamics, or heartbeat "
        "with Inertia = true); quasi-static solves see no velocity. 1 Pa s/m = 1e-3 kPa ms/mm (Arostica et al. "
        "2025: 5e3 Pa s/m = 5). Units: kPa ms/mm.");
      prm.declare_entry(
        "Robin supports",
        "",
        Anything(),
        "Spring-dashpot supports with their own values, one per boundary part: "
        "'part: normal|tangential|full, alpha, beta; part: ...' gives the "
        "traction -(alpha u + beta v) per reference area on the normal "
        "component (normal: ((alpha u + beta v).N) N), on the tangential ones "
        "(tangential: a base that may descend but not slide or turn) or on all "
        "components (full; 'full r' scales the normal stiffness and damping "
        "by r: a base held against turning more than against descending). "
        "alpha in kPa/mm (1 Pa/m = 1e-6 kPa/mm), beta in kPa ms/mm "
        "(1 Pa s/m = 1e-3 kPa ms/mm); the benchmark of Arostica et al. 2025: "
        "'epicardium: normal, 100, 5; base: full, 0.1, 5'. An optional fourth "
        "item 'taper h0 s_base' scales alpha and beta from the apex to the "
        "base (a pericardium that holds the apex and lets the base descend, "
        "after Strocchi et al. 2020): by 1 up to the height fraction h0 above "
        "the apex, then linearly down to s_base at the base plane (h = 1; h "
        "is the distance from the apex, the part's point farthest from the "
        "base's best-fit plane, over the apex's distance; needs a part "
        "'base'). The option 'end-diastole' refers the springs to the "
        "displacement at the last end-diastole instead of the unloaded state "
        "(a heartbeat; from the first ventricle's inlet valve closure on, the "
        "unloaded state before it): they hold the base where the filled "
        "ventricle put it and do not oppose its filling. 'end-diastole T' "
        "moves the rest position there over T ms instead of at once (a "
        "smooth step from the last rest position; the same T for every such "
        "support): released at once, the springs drop the pressure of the "
        "closed cavity, and the inlet valve opens and closes again. A part "
        "may not be in Robin boundaries as well. Units: kPa/mm, kPa ms/mm, "
        "ms.");
    }

    /// The active stress and how the loads act (lid pressure, volumetric rule).
    void
    declare_active_stress(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Active tension",
        "0",
        Double(0.0),
        "Prescribed active tension T_a at the end of the load "
        "ramp: S_a = T_a f0 x f0 (2nd Piola-Kirchhoff, per "
        "reference area, along the reference fibre; >= 0: the fibres "
        "contract). Units: kPa.");
      prm.declare_entry(
        "Active sheet fraction",
        "0",
        Double(0.0, 1.0),
        "Fraction eta_s of the active tension that acts along the sheet "
        "direction s0: S_a = T_a (f0 x f0 + eta_s s0 x s0 + eta_n n0 x n0) "
        "(Sommer et al. 2015; fenicsx-pulse's transversely isotropic eta is "
        "eta_s = eta_n = eta). With the Land model (stretch-dependent) the "
        "tangent is not symmetric and the direct solver uses LU. Units: -.");
      prm.declare_entry(
        "Lid pressure",
        "false",
        Bool(),
        "With a base that is not held in its plane (on springs), where each "
        "cavity is closed by the fan over its moving rim: true lets the "
        "cavity pressure act on that lid as well, its force reaching the wall "
        "through the rim (spread evenly over the rim vertices), so that the "
        "load is p dV/du of the closed cavity and the pressure exerts no net "
        "force on the ventricle (as the closed valves pass it to the annulus; "
        "energy-consistent, after Regazzoni et al. 2022, J Comput Phys "
        "457:111083); its tangent couples the rim to the whole wall (rank 6 "
        "per cavity, applied by Woodbury in the solves). false: the pressure "
        "acts on the endocardium only (the benchmark of Arostica et al. "
        "2025).");
      prm.declare_entry("Active normal fraction",
                        "0",
                        Double(0.0, 1.0),
                        "Fraction eta_n of the active tension that acts along "
                        "the sheet-normal direction n0 (see Active sheet "
                        "fraction). Units: -.");
      prm.declare_entry(
        "Volumetric integration",
        "full",
        Selection("full|reduced"),
        "full: the volumetric penalty is integrated with the "
        "same Gauss rule as the rest; reduced: Q2 elements "
        "integrate it with 2 x 2 x 2 points (selective reduced "
        "integration), which relieves the volumetric locking of "
        "thin, bending-dominated bodies (Land problem 1) but "
        "makes Newton less robust on the ventricle. Q1 elements "
        "always use the full rule. Units: -.");
    }

    /// The load ramp and its step control.
    void
    declare_load_steps(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Load steps",
        "5",
        Integer(1),
        "The first increment of the load ramp (from zero to the "
        "full pressure and active tension) is 1 / Load steps. "
        "Later increments adapt: x1.5 after a load step that "
        "took at most 4 Newton iterations, x0.5 after one that "
        "took 8 or more or failed. Units: -.");
      prm.declare_entry(
        "Adaptive load steps",
        "true",
        Bool(),
        "true: the load increments adapt to the Newton "
        "iterations (see Load steps); false: every increment is "
        "1 / Load steps (halved only when Newton fails). "
        "Units: -.");
      prm.declare_entry("Maximum step cuts",
                        "8",
                        Integer(0, 30),
                        "How many times a load step may be halved when Newton "
                        "fails before the run stops with an error. Units: -.");
    }

    /// Newton's method: tolerances and the reuse of the tangent.
    void
    declare_newton(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry("Newton relative tolerance",
                        "1e-9",
                        Double(0.0),
                        "Newton converges when the residual norm falls below "
                        "this fraction of the largest residual norm of the "
                        "load step (or when an update is at round-off level, "
                        "|du| <= 1e-12 |u|). Units: -.");
      prm.declare_entry("Newton absolute tolerance",
                        "1e-12",
                        Double(0.0),
                        "... or below this absolute value. Units: kPa mm^2 "
                        "(force, mN).");
      prm.declare_entry(
        "Cavity volume tolerance",
        "2e-9",
        Double(1e-14, 1e-3),
        "A solve with cavity volume constraints (the heartbeat's coupled "
        "step, a volume target) converges only when every cavity volume is "
        "also within this fraction of its target. The shipped heartbeats "
        "use 1e-7 (with Newton relative tolerance = 1e-4): against 2e-9 "
        "and 1e-5 their pressures move by at most 0.002 mmHg, far below "
        "the time integration's error (Circulation / Relative tolerance; "
        "docs/verification.md). Units: -.");
      prm.declare_entry("Maximum Newton iterations",
                        "12",
                        Integer(1),
                        "Iterations before a load step counts as failed and is "
                        "cut. A converging Newton needs 3 to 6 (chord "
                        "iterations, see Reuse factorization, do not count). "
                        "Units: -.");
      prm.declare_entry(
        "Reuse factorization",
        "true",
        Bool(),
        "true: Newton reuses the factorized (or preconditioned) tangent where "
        "that is cheaper than a new one: a solve after a converged one starts "
        "with a chord iteration on the last tangent (the Euler predictor of the "
        "new load; for volume-constrained solves, chord iterations while they "
        "converge fast); with the direct solver, after a Newton update that "
        "cut the residual tenfold to below 0.1 of its largest value, or a "
        "chord update that cut it fourfold, the next update is a chord "
        "iteration too (at most 20 per solve; one that raises the residual is "
        "undone); with an "
        "iterative solver, the preconditioner is reused at most three times "
        "per solve once the residual is below 1e-3 of its largest value and "
        "fell tenfold in the last iteration. false: a new tangent and "
        "factorization at every iteration (pure Newton, e.g. to see its "
        "quadratic convergence). Units: -.");
      prm.declare_entry(
        "Chord acceleration depth",
        "auto",
        dealii::Patterns::Anything(),
        "With the direct solver and fixed cavity pressures, > 0: the chord "
        "iterations (see Reuse factorization) are Anderson-accelerated with "
        "this many past updates (Walker and Ni 2011: a least-squares "
        "combination that damps the error modes the held factorization "
        "contracts slowly; an accelerated update over 3 times the plain one "
        "is not taken). They then also continue the Euler predictor on the "
        "last solve's factorization, continue while each cuts the residual "
        "twofold instead of fourfold, and follow a Newton update that cut it "
        "2.5-fold to below 0.4 of its largest value; a chord update at least "
        "half as long as the update before it is not taken, and one that "
        "cut the residual less than twofold is undone (Newton from the "
        "iterate). Fewer factorizations (Land problem 2, 10 equal load steps, "
        "129k DOFs: 8 instead of 13, 66-78 s instead of 89-98 s on 2 ranks), "
        "more chord iterations, so it pays where factorizations dominate. "
        "0: plain chord iterations with the rules of Reuse factorization; "
        "auto: 5 with at least 50000 DOFs, 0 below (17.9k DOFs: 5.1-6.2 s "
        "accelerated, 5.8-6.2 s plain: within the noise). In "
        "volume-constrained solves (the heartbeat) an explicit depth "
        "accelerates only the chord iterations that start a solve on an "
        "earlier solve's factorization, their rules unchanged, the cavity "
        "pressures' updates combined with the displacement's coefficients; "
        "auto leaves them plain (iterations with depth 5 against plain, the "
        "same volumes to 4 digits: lv_heartbeat 2711 against 2765, "
        "lv_closed_loop 2201 against 2277, biv_heartbeat 3582 against 3412). "
        "An integer 0-50 or auto. Units: -.");
    }

    /// The inertia and damping of time integrations.
    void
    declare_inertia(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Density",
        "1000",
        Double(0.0),
        "Mass density of the tissue, for the inertia of time-dependent runs "
        "that include it (Problem::set_time_step; the quasi-static problems "
        "ignore it). Units: kg/m^3 (1000 kg/m^3 = 1 mg/mm^3, the code's unit).");
      prm.declare_entry(
        "Inertia",
        "false",
        Bool(),
        "Problem = heartbeat: true integrates the mechanics of the cardiac "
        "cycle with its inertia (Density), Rayleigh mass damping, Viscosity and "
        "the dashpots of the Robin supports, one generalized-alpha step "
        "(Spectral radius) per heartbeat step, the cavity pressures the "
        "multipliers of the volume constraints as in the quasi-static beat; "
        "false: every step is a quasi-static equilibrium (the rates and the "
        "density are ignored). Every Material / Incompressibility: the mixed "
        "formulations' pressure is the multiplier of the volume, without "
        "inertia or rates. Problem = elastodynamics always has inertia. "
        "Units: -.");
      prm.declare_entry(
        "Spectral radius",
        "0.8",
        Double(0.0, 1.0),
        "Spectral radius at infinite frequency of the generalized-alpha time "
        "integration of the inertia (Chung and Hulbert 1993): 1 keeps every "
        "frequency undamped (the trapezoidal rule, energy-conserving for "
        "linear problems), smaller values damp the highest frequencies of the "
        "mesh; second order for every value. In a heartbeat (Inertia = true) "
        "0.5 damps the ringing of those frequencies at the valve closures, "
        "which with 0.8 makes the mitral valve chatter (docs/verification.md). "
        "Units: -.");
      prm.declare_entry(
        "Rayleigh mass damping",
        "0",
        Double(0.0),
        "Damping proportional to the mass, C = c_M M, in time-dependent runs "
        "with inertia. Units: 1/s.");
      prm.declare_entry(
        "Viscosity",
        "0",
        Double(0.0),
        "Kelvin-Voigt viscosity eta of the tissue in time integrations with "
        "inertia: the 2nd Piola-Kirchhoff stress eta dE/dt (E the Green strain) "
        "adds to the elastic one; quasi-static solves see no rate. Arostica et "
        "al. 2025: 0.1 kPa s (= 100 Pa s). Units: kPa s (1 kPa s = 1000 kPa "
        "ms, the code's unit).");
    }

    /// The linear solver and its preconditioners.
    void
    declare_linear_solver(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Linear solver",
        "auto",
        Selection("auto|direct|iterative|matrix-free"),
        "direct: MUMPS (LDL^T when the tangent is symmetric, else LU); "
        "iterative: for the penalty formulation FGMRES with the "
        "p-multigrid or GMRES with PETSc GAMG (algebraic multigrid "
        "given the rigid-body modes; see Displacement "
        "preconditioner), for the mixed ones FGMRES with a block "
        "preconditioner (that V-cycle on the displacement block, "
        "the pressure mass matrix scaled by 1/mu + 1/kappa for "
        "the Schur complement; PETSc options with the prefix "
        "-mechanics_ override it); matrix-free: no sparse tangent, the "
        "tangent applied matrix-free (sum factorization on the cached "
        "dP/dF of every quadrature point, the follower pressure on its "
        "faces) with CG (GMRES if not symmetric) and a p-multigrid V-cycle: "
        "Chebyshev smoothing with the matrix-free diagonal on Q2, the Q1 "
        "matrix of the same cached tangent solved by MUMPS (PETSc prefix "
        "-mechanics_mf_coarse_); for the mixed formulations (Q2-P1disc) "
        "FGMRES on the augmented system applied cell by cell (the pressure "
        "rows and the Augmented Lagrangian factor's term at the points) with "
        "the iterative solver's block preconditioner on that V-cycle; only "
        "Q2 hexahedra, quasi-static, without volume constraints, loaded lids "
        "or spring supports (else an error naming iterative and direct); "
        "auto: direct up to 'Direct solver limit' DOFs, above it "
        "matrix-free where it applies and the problem solves at given "
        "pressures (Problem = mechanics), else iterative. Units: -.");
      prm.declare_entry(
        "Direct solver limit",
        "200000",
        Integer(0),
        "Largest number of DOFs for which 'auto' uses the direct "
        "solver. Units: DOFs.");
      prm.declare_entry("Linear solver tolerance",
                        "1e-8",
                        Double(0.0, 1.0),
                        "Relative residual reduction of the iterative solver "
                        "(with Inexact Newton: of its most accurate solves). "
                        "Units: -.");
      prm.declare_entry(
        "Inexact Newton",
        "true",
        Bool(),
        "true: with the iterative and the matrix-free solver (not the direct "
        "one, nor the volume-constrained solves of the heartbeat), each Newton "
        "and chord update is solved only as accurately as Newton's convergence "
        "needs: to the relative residual eta = 0.9 (|R_k| / |R_k-1|)^2 "
        "(Eisenstat and Walker 1996, choice 2), at most 0.01 (also the Euler "
        "predictor's), at least 0.5 (Newton tolerance) / |R_k|, for a chord "
        "update at least 0.1 |R_k| / |R_k-1| (a chord converges linearly), "
        "and at least Linear solver tolerance. The same solution in fewer Krylov "
        "iterations (Land problem 2, incompressible, 129k DOFs, iterative: "
        "606 instead of 1711, 141 s instead of 297 s on 2 ranks), a few more "
        "Newton iterations. false: every solve to Linear solver tolerance "
        "(Newton iterates comparable between linear solvers). Units: -.");
      prm.declare_entry(
        "Displacement preconditioner",
        "p-multigrid",
        Selection("amg|p-multigrid"),
        "Preconditioner of the displacement (the displacement block of the "
        "mixed formulations) in the iterative linear solver. p-multigrid: a "
        "two-level V-cycle, three Chebyshev iterations with point-block Jacobi "
        "on Q2, then an exact solve (MUMPS LU) with the Galerkin operator P^T A "
        "P of the Q1 displacement of the same mesh (P the interpolation Q1 -> "
        "Q2, built once per mesh); amg: one PETSc GAMG V-cycle on the Q_k "
        "displacement (rigid-body modes as near-null space). On the measured "
        "cases "
        "p-multigrid takes less solver time (a third of the Krylov iterations "
        "on the incompressible ventricle; docs/architecture.md). Q1 "
        "displacements have no coarser degree and use amg (the run banner says "
        "so). PETSc options with the prefix -mechanics_fieldsplit_u_pmg_ "
        "(penalty: -mechanics_pmg_) override the smoother and the coarse "
        "solver. Units: -.");
      prm.declare_entry(
        "Augmented Lagrangian factor",
        "1",
        Double(0.0, 100.0),
        "The iterative solver of the mixed formulations with a discontinuous "
        "pressure solves the system multiplied by T = [I, gamma B^T W^-1; 0, "
        "I] (an augmented Lagrangian: the same solution; B the pressure rows "
        "of the tangent, W the pressure mass matrix weighted by 1/kappa + "
        "1/mu, block-diagonal by cells): its displacement block A + gamma B^T "
        "W^-1 B then resists a change of volume as a bulk modulus of about "
        "gamma mu would, where the isochoric law alone does not (A is "
        "singular on dilations), and the scaled pressure mass matrix becomes a "
        "mesh-independent approximation of its Schur complement. This is "
        "gamma; 0 solves the plain saddle-point system. Ignored by the direct "
        "solver, the penalty formulation and the continuous pressure. Must be "
        "below (kappa + mu) / mu. Units: -.");
    }

    /// What the mechanics adds to the time series.
    void
    declare_output(dealii::ParameterHandler &prm)
    {
      prm.declare_entry(
        "Tracked points",
        "",
        dealii::Patterns::Anything(),
        "Reference points whose deformed position is written to "
        "the time series: 'name: x, y, z; name: x, y, z' gives "
        "columns name_x, name_y, name_z. Units: mm.");
    }
  } // namespace

  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Mechanics");
    declare_boundaries(prm);
    declare_active_stress(prm);
    declare_load_steps(prm);
    declare_newton(prm);
    declare_inertia(prm);
    declare_linear_solver(prm);
    declare_output(prm);
    prm.leave_subsection();
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> m = {"Mechanics"};
    Parameters                     p;
    p.fixed_boundaries   = names(prm.get(m, "Fixed boundaries"));
    p.sliding_boundaries = names(prm.get(m, "Sliding boundaries"));
    p.pressure_boundary  = prm.get(m, "Pressure boundary");
    p.pressure           = prm.get_double(m, "Pressure");
    p.robin_boundaries   = names(prm.get(m, "Robin boundaries"));
    p.robin_stiffness    = prm.get_double(m, "Robin stiffness");
    p.robin_normal_only  = prm.get(m, "Robin type") == "normal";
    p.robin_damping      = prm.get_double(m, "Robin damping");
    p.robin_supports     = parse_robin_supports(prm.get(m, "Robin supports"));
    p.active_tension     = prm.get_double(m, "Active tension");
    p.active_cross_fibre.sheet  = prm.get_double(m, "Active sheet fraction");
    p.active_cross_fibre.normal = prm.get_double(m, "Active normal fraction");
    p.lid_pressure              = prm.get_bool(m, "Lid pressure");
    p.reduced_volumetric_integration =
      prm.get(m, "Volumetric integration") == "reduced";
    p.load_steps          = prm.get_integer(m, "Load steps");
    p.max_step_cuts       = prm.get_integer(m, "Maximum step cuts");
    p.adaptive_load_steps = prm.get_bool(m, "Adaptive load steps");
    const std::string incompressibility =
      prm.get({"Material"}, "Incompressibility");
    p.incompressibility = incompressibility == "penalty"
                            ? Incompressibility::penalty
                          : incompressibility == "incompressible"
                            ? Incompressibility::incompressible
                            : Incompressibility::nearly_incompressible;
    p.pressure_element =
      prm.get({"Discretization"}, "Pressure element") == "continuous"
        ? PressureElement::continuous
        : PressureElement::discontinuous;
    p.newton_relative_tolerance =
      prm.get_double(m, "Newton relative tolerance");
    p.newton_absolute_tolerance =
      prm.get_double(m, "Newton absolute tolerance");
    p.cavity_volume_tolerance = prm.get_double(m, "Cavity volume tolerance");
    p.max_newton_iterations   = prm.get_integer(m, "Maximum Newton iterations");
    p.reuse_factorization     = prm.get_bool(m, "Reuse factorization");
    {
      const std::string depth   = prm.get(m, "Chord acceleration depth");
      p.chord_acceleration_auto = depth == "auto";
      if (!p.chord_acceleration_auto)
        {
          const dealii::Patterns::Integer valid(0, 50);
          AssertThrow(valid.match(depth),
                      dealii::ExcMessage(
                        "Mechanics / Chord acceleration depth = '" + depth +
                        "': give auto, or an integer from 0 (plain chord "
                        "iterations) to 50."));
          p.chord_acceleration_depth = dealii::Utilities::string_to_int(depth);
        }
    }
    p.linear_solver       = prm.get(m, "Linear solver");
    p.direct_solver_limit = prm.get_integer(m, "Direct solver limit");
    p.linear_tolerance    = prm.get_double(m, "Linear solver tolerance");
    p.inexact_newton      = prm.get_bool(m, "Inexact Newton");
    p.displacement_preconditioner =
      prm.get(m, "Displacement preconditioner") == "amg"
        ? DisplacementPreconditioner::amg
        : DisplacementPreconditioner::p_multigrid;
    p.augmented_lagrangian  = prm.get_double(m, "Augmented Lagrangian factor");
    p.tracked_points        = parse_points(prm.get(m, "Tracked points"));
    p.density               = 1e-3 * prm.get_double(m, "Density");
    p.spectral_radius       = prm.get_double(m, "Spectral radius");
    p.rayleigh_mass_damping = 1e-3 * prm.get_double(m, "Rayleigh mass damping");
    p.viscosity             = 1e3 * prm.get_double(m, "Viscosity");
    AssertThrow(p.robin_boundaries.empty() || p.robin_stiffness > 0 ||
                  p.robin_damping > 0,
                dealii::ExcMessage(
                  "Mechanics / Robin boundaries are set but Robin stiffness "
                  "and Robin damping are 0: give the spring stiffness in "
                  "kPa/mm (or the damping in kPa ms/mm)."));
    const auto supports = p.all_robin_supports();
    for (unsigned int i = 0; i < supports.size(); ++i)
      for (unsigned int j = 0; j < i; ++j)
        AssertThrow(supports[i].boundary != supports[j].boundary,
                    dealii::ExcMessage(
                      "Mechanics / Robin boundaries and Robin supports name "
                      "the boundary part '" +
                      supports[i].boundary +
                      "' twice: give each part one support."));
    AssertThrow(p.pressure == 0.0 || !p.pressure_boundaries().empty(),
                dealii::ExcMessage("Mechanics / Pressure is not zero but "
                                   "Pressure boundary is empty: name the "
                                   "boundary part that carries it."));
    AssertThrow(!(p.mixed() && p.reduced_volumetric_integration),
                dealii::ExcMessage(
                  "Mechanics / Volumetric integration = reduced is a remedy "
                  "of the penalty formulation; with Material / "
                  "Incompressibility = " +
                  incompressibility +
                  " the pressure field already removes the locking: set it "
                  "to full."));
    return p;
  }

  std::vector<RobinSupport>
  Parameters::parse_robin_supports(const std::string &text)
  {
    return parse_supports(text);
  }

  dealii::Tensor<2, 3>
  RobinSupport::projection(const dealii::Tensor<1, 3> &N) const
  {
    const dealii::Tensor<2, 3> nn = dealii::outer_product(N, N);
    if (normal_only)
      return nn;
    const dealii::Tensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    return tangential_only ? I - nn : I - (1.0 - normal_fraction) * nn;
  }

  double
  RobinSupport::scale(const dealii::Point<3> &X) const
  {
    if (!tapered())
      return 1.0;
    const double h =
      std::clamp(1.0 - ((base_point - X) * apex_to_base) / height, 0.0, 1.0);
    if (h <= taper_start)
      return 1.0;
    return 1.0 - (1.0 - base_scale) * (h - taper_start) / (1.0 - taper_start);
  }

  std::vector<RobinSupport>
  Parameters::all_robin_supports() const
  {
    std::vector<RobinSupport> supports;
    for (const auto &part : robin_boundaries)
      supports.push_back(
        {part, robin_stiffness, robin_damping, robin_normal_only});
    supports.insert(supports.end(),
                    robin_supports.begin(),
                    robin_supports.end());
    return supports;
  }

  std::vector<std::string>
  Parameters::pressure_boundaries() const
  {
    return names(pressure_boundary);
  }

  void
  Parameters::declare_incompressibility(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "Incompressibility",
      "penalty",
      dealii::Patterns::Selection(
        "penalty|nearly incompressible|incompressible"),
      "How the volume of the tissue is held. penalty: displacement only, "
      "the volumetric energy U(J) of subsection Volumetric added to the "
      "stress (locks in bending with the full Gauss rule); nearly "
      "incompressible: mixed displacement-pressure formulation with the "
      "energy -p (J - 1) - p^2 / (2 kappa), kappa = Volumetric / Bulk "
      "modulus (the quadratic form of U whatever Volumetric / Form says); "
      "incompressible: the same with 1/kappa = 0, J = 1 exactly in the "
      "pressure space. The mixed formulations use the isochoric part of the "
      "passive law (the law at F J^(-1/3)), so that the pressure alone "
      "governs the volume. The pressure p [kPa] is positive in compression. "
      "Units: -.");
  }

  void
  Parameters::declare_pressure_element(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "Pressure element",
      "discontinuous",
      dealii::Patterns::Selection("discontinuous|continuous"),
      "Pressure space of the mixed formulations (Material / "
      "Incompressibility not penalty). discontinuous: Q_k-P_{k-1}disc "
      "(Q2-P1disc, inf-sup stable; Q1-P0, the mean-dilatation element), "
      "element-wise incompressibility and a block-diagonal pressure mass "
      "matrix; continuous: Taylor-Hood Q_k-Q_{k-1} (needs Polynomial degree "
      "2). On coarse meshes continuous is the more accurate: on Land problem "
      "2's ventricle with 24 or 64 cells (one through the wall) its apexes lie "
      "inside the benchmark's band, Q2-P1disc's epicardial apex 0.36 mm from "
      "the converged value, outside; from about 10k DOFs the two agree within "
      "the band. discontinuous is the faster on large meshes: only it has the "
      "iterative solver's augmented Lagrangian (docs/verification.md, Land "
      "problem 2: incompressible). Units: -.");
  }
} // namespace systole::Mechanics
