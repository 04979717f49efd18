#include "simulation/parameters.h"

#include <deal.II/base/parameter_handler.h>

#include "base/parameter_table.h"
#include "circulation/model_factory.h"
#include "circulation/parameters.h"
#include "electrophysiology/parameters.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "materials/bestel.h"
#include "materials/factory.h"
#include "materials/land.h"
#include "materials/tension_factory.h"
#include "mechanics/parameters.h"
#include "simulation/problem_type.h"

#include "postprocess/manager.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <utility>
#include <vector>

namespace systole
{
  namespace
  {
    /// The subsection path ("Geometry / Ellipsoid") in force at line @p line of
    /// a .prm file.
    std::string
    subsection_at_line(const std::string &file, const unsigned int line)
    {
      std::ifstream            in(file);
      std::vector<std::string> path;
      std::string              text;
      for (unsigned int n = 1; n < line && std::getline(in, text); ++n)
        {
          const auto words = dealii::Utilities::split_string_list(
            dealii::Utilities::trim(text.substr(0, text.find('#'))),
            ' ');
          if (words.empty())
            continue;
          if (words[0] == "subsection")
            path.push_back(dealii::Utilities::trim(
              text.substr(text.find("subsection") + 10,
                          text.find('#') == std::string::npos
                            ? std::string::npos
                            : text.find('#') - text.find("subsection") - 10)));
          else if (words[0] == "end" && !path.empty())
            path.pop_back();
        }
      std::string joined;
      for (const auto &p : path)
        joined += (joined.empty() ? "" : " / ") + p;
      return joined.empty() ? "the top level" : "subsection '" + joined + "'";
    }

    /// "line N: subsection 'X' has no 'end' line" for the first subsection of
    /// @p file left open at its end ("" if none).
    std::string
    unclosed_subsection(const std::string &file)
    {
      std::ifstream                                     in(file);
      std::vector<std::pair<unsigned int, std::string>> open;
      std::string                                       text;
      for (unsigned int n = 1; std::getline(in, text); ++n)
        {
          const std::string code =
            dealii::Utilities::trim(text.substr(0, text.find('#')));
          if (code.rfind("subsection ", 0) == 0)
            open.emplace_back(n, dealii::Utilities::trim(code.substr(11)));
          else if (code == "end" && !open.empty())
            open.pop_back();
        }
      if (open.empty())
        return "";
      return "line " + std::to_string(open.front().first) + ": subsection '" +
             open.front().second + "' has no 'end' line.";
    }

    /// One clear sentence from deal.II's parse error: file, line, entry,
    /// subsection.
    std::string
    describe_parse_error(const std::string &file, const std::string &info)
    {
      // deal.II omits the '>' after the file name in some messages.
      const std::regex line_re("Line <([0-9]+)> of file <[^>:]*>?:");
      const std::regex entry_re(
        "No entry with name <([^>]*)> was declared in the current subsection");
      const std::regex section_re(
        "There is no such subsection to be entered: ([^\n]*)");
      std::smatch       line_match, entry_match, section_match;
      const std::string hint =
        " Run 'systole --print-parameters' for every entry with its documentation.";
      if (std::regex_search(info, line_match, line_re))
        {
          const unsigned int line  = std::stoul(line_match[1]);
          const std::string  where = "parameter file '" + file + "', line " +
                                    std::to_string(line) + ": ";
          if (std::regex_search(info, entry_match, entry_re))
            return where + "unknown entry '" + entry_match[1].str() + "' in " +
                   subsection_at_line(file, line) + " (misspelt?)." + hint;
          if (std::regex_search(info, section_match, section_re))
            {
              // deal.II joins the path with '.': the last part is the name.
              const std::string path =
                dealii::Utilities::trim(section_match[1].str());
              const auto dot = path.rfind('.');
              return where + "unknown subsection '" +
                     path.substr(dot == std::string::npos ? 0 : dot + 1) +
                     "' in " + subsection_at_line(file, line) +
                     " (misspelt, or an 'end' line missing before it?)." + hint;
            }
          return where + std::string(line_match.suffix()) + hint;
        }
      if (info.find("unequal numbers of 'subsection' and 'end'") !=
            std::string::npos &&
          !unclosed_subsection(file).empty())
        return "parameter file '" + file + "', " + unclosed_subsection(file) +
               hint;
      return "parameter file '" + file + "': " + info + hint;
    }

    /// Subsection Discretization: the elements and the mapping.
    void
    declare_discretization(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.enter_subsection("Discretization");
      prm.declare_entry(
        "Polynomial degree",
        "1",
        Integer(1, 2),
        "Degree of the Lagrange elements of the displacement (Q1 or Q2). Units: -.");
      prm.declare_entry(
        "Mapping degree",
        "2",
        Integer(1, 4),
        "Degree of the polynomial geometry of curved cells (1: straight edges). "
        "Tetrahedra: 2 or more maps the cells of a file of 10-node tetrahedra "
        "quadratically through its mid-edge nodes; other tetrahedral meshes "
        "are affine. Units: -.");
      Mechanics::Parameters::declare_pressure_element(prm);
      prm.leave_subsection();
    }


    /// The test-only entries of subsection Output (the checkpoint,
    /// write-failure and rank tests); -1: never.
    const std::vector<IntegerEntry<RunParameters>> &
    test_hooks()
    {
      using dealii::Patterns::Integer;
      static const std::vector<IntegerEntry<RunParameters>> table = {
        {"Test kill after step",
         &RunParameters::test_kill_after_step,
         Integer(-1),
         "Test-only (checkpoint tests): Problem = heartbeat (electrophysiology) "
         "kills itself with SIGKILL after this accepted step (and its checkpoint, if one is due), "
         "as a crash would; -1: never. Units: steps."},
        {"Test kill in checkpoint",
         &RunParameters::test_kill_in_checkpoint,
         Integer(-1),
         "Test-only (checkpoint tests): Problem = heartbeat kills itself with "
         "SIGKILL halfway through writing the checkpoint of this step; -1: "
         "never. Units: steps."},
        {"Test file size limit in checkpoint",
         &RunParameters::test_file_size_limit_in_checkpoint,
         Integer(-1),
         "Test-only (write-failure tests): Problem = heartbeat limits the size "
         "of the files it writes to 1 kB (RLIMIT_FSIZE, SIGXFSZ ignored) before "
         "writing the checkpoint of this step, so that its writes fail as on a "
         "full disk; -1: never. Units: steps."},
        {"Test file size limit after step",
         &RunParameters::test_file_size_limit_after_step,
         Integer(-1),
         "Test-only (write-failure tests): Problem = heartbeat limits the size "
         "of the files it writes to the present size of its results file "
         "(RLIMIT_FSIZE, SIGXFSZ ignored) after this accepted step, so that the "
         "next write that grows the results file fails as on a full disk; -1: "
         "never. Units: steps."},
        {"Test stop after step",
         &RunParameters::test_stop_after_step,
         Integer(-1),
         "Test-only (the short runs of the rank tests): Problem = heartbeat ends "
         "after this accepted step, its fields and rows written, as an "
         "interrupted run ends but without a checkpoint; -1: never. Units: "
         "steps."}};
      return table;
    }


    /// Subsection Output: where the results go, how often, and the
    /// checkpoints.
    void
    declare_output(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.enter_subsection("Output");
      prm.declare_entry(
        "Run name",
        "",
        Anything(),
        "Name of the run; results go to <Directory>/<Run name>/results.h5. "
        "Empty: the parameter file's name without extension.");
      prm.declare_entry(
        "Directory",
        "results",
        FileName(FileName::output),
        "Folder that holds the run folders, relative to the working directory.");
      prm.declare_entry(
        "Field output interval",
        "10",
        Integer(0),
        "Write the fields (displacement, ...) every this many steps, and at the "
        "first and last step; 0 writes none. Units: steps.");
      prm.declare_entry(
        "Solver log",
        "auto",
        Selection("auto|on|off"),
        "Newton residual histories of every mechanics solve on the console. "
        "auto: on for the load steps of the mechanics problem, off for the "
        "heartbeat (thousands of solves; its time series has the iteration "
        "counts).");
      prm.declare_entry(
        "Checkpoint interval",
        "0",
        Integer(0),
        "Problem = heartbeat, electrophysiology and elastodynamics: write a checkpoint (the "
        "whole state of the run, "
        "in <Directory>/<Run name>/checkpoint_NNNNNN; the last two are kept) "
        "every this many accepted steps; 0: none by step count. A checkpoint is "
        "also written when the run receives SIGTERM or SIGINT. Units: steps.");
      prm.declare_entry(
        "Checkpoint wall time interval",
        "0",
        Double(0.0),
        "Problem = heartbeat, electrophysiology and elastodynamics: write a checkpoint at the "
        "end of the first step "
        "after this much wall-clock time since the start or the last "
        "checkpoint; 0: none by wall time. Units: minutes.");
      prm.declare_entry(
        "Resume",
        "false",
        Bool(),
        "Problem = heartbeat, electrophysiology and elastodynamics: continue the run in "
        "<Directory>/<Run name> from "
        "its newest valid checkpoint, appending to its results.h5 (rows written "
        "after that checkpoint are discarded first). The parameter file must "
        "describe the same problem as the one the checkpoint was written with "
        "(only subsection Output may differ). `systole --resume "
        "<Directory>/<Run name>` does the same with the parameter file the run "
        "was started with. Units: -.");
      prm.declare_entry(
        "Progress",
        "auto",
        Selection("auto|on|off"),
        "Progress line on the console (step, time, activity, elapsed, ETA). "
        "auto: on when the output is a terminal and the CI variable is unset.");
      declare_entries(prm, test_hooks());
      prm.leave_subsection();
    }


    /// Subsection Time: the interval and step of the time loop.
    void
    declare_time(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.enter_subsection("Time");
      prm.declare_entry("Start time",
                        "0",
                        Double(),
                        "Simulated time of the first step. Units: ms.");
      prm.declare_entry("End time",
                        "100",
                        Double(),
                        "Simulated time of the last step. Units: ms.");
      prm.declare_entry(
        "Time step",
        "10",
        Double(0.0),
        "Step of the time loop (an upper bound once steps adapt). Units: ms.");
      prm.leave_subsection();
    }

  } // namespace

  void
  declare_all_parameters(dealii::ParameterHandler &prm)
  {
    problem_types().declare_selection(prm,
                                      "Problem",
                                      "cavity volume",
                                      "What to simulate.");
    problem_types().declare_parameters(prm, /*own_subsections=*/false);
    declare_time(prm);
    declare_output(prm);
    declare_discretization(prm);
    Geometry::Parameters::declare(prm);
    Fibres::Parameters::declare(prm);
    Materials::declare_parameters(prm);
    prm.enter_subsection("Material");
    Mechanics::Parameters::declare_incompressibility(prm);
    prm.leave_subsection();
    Mechanics::Parameters::declare(prm);
    Materials::declare_tension_parameters(prm);
    Circulation::Parameters::declare(prm);
    Circulation::declare_model_parameters(prm);
    Electrophysiology::Parameters::declare(prm);
    Postprocess::Parameters::declare(prm);
  }

  void
  read_parameter_file(dealii::ParameterHandler &prm, const std::string &file)
  {
    AssertThrow(std::filesystem::is_regular_file(file),
                dealii::ExcMessage("Cannot open the parameter file '" + file +
                                   "' (no such file)."));
    declare_all_parameters(prm);
    try
      {
        prm.parse_input(file,
                        "",
                        /*skip_undefined=*/false,
                        /*assert_mandatory_entries_are_found=*/true);
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        AssertThrow(false,
                    dealii::ExcMessage(describe_parse_error(file, info.str())));
      }
  }

  void
  validate_component_parameters(const dealii::ParameterHandler &prm,
                                const std::string              &file)
  {
    const std::string directory =
      std::filesystem::absolute(file).parent_path().string();
    Geometry::Parameters::parse(prm, directory);
    const auto fibres = Fibres::Parameters::parse(prm, directory);
    if (fibres.generator == "dti")
      Fibres::DTIField check(fibres.dti); // reads the file: errors now
    AssertThrow((fibres.generator != "analytic" &&
                 fibres.generator != "arostica") ||
                  prm.get({"Geometry"}, "Type") == "ellipsoid" ||
                  prm.get({"Geometry"}, "Type") == "arostica" ||
                  (prm.get({"Geometry"}, "Type") == "gmsh" &&
                   prm.get({"Geometry", "Gmsh"}, "Shape") == "arostica"),
                dealii::ExcMessage(
                  "Fibres / Generator = " + fibres.generator +
                  " needs a generated ventricle (Geometry / Type = ellipsoid "
                  "or arostica) or a mesh file of a known shape (Geometry / "
                  "Gmsh / Shape = arostica): the helix rule is defined in its "
                  "ellipsoidal coordinates."));
    Materials::create_passive_law(prm);
    Materials::create_volumetric_law(prm);
    Mechanics::Parameters::parse(prm);
    Materials::Bestel::Parameters::parse(prm);
    Materials::Land::Parameters::parse(prm);
    Circulation::Parameters::parse(prm);
    Circulation::create_model(prm);
    Electrophysiology::Parameters::parse(prm);
    Postprocess::Parameters::parse(prm);
    problem_types().create(prm.get("Problem"))->parse_parameters(prm);
  }

  RunParameters
  RunParameters::parse(const dealii::ParameterHandler &prm,
                       const std::string              &prm_file)
  {
    RunParameters p;
    p.problem    = prm.get("Problem");
    p.start_time = prm.get_double({"Time"}, "Start time");
    p.end_time   = prm.get_double({"Time"}, "End time");
    p.time_step  = prm.get_double({"Time"}, "Time step");
    AssertThrow(p.end_time >= p.start_time,
                dealii::ExcMessage(
                  "Time / End time (" + std::to_string(p.end_time) +
                  " ms) must not be smaller than Time / Start time (" +
                  std::to_string(p.start_time) + " ms)."));
    AssertThrow(p.time_step > 0,
                dealii::ExcMessage("Time / Time step must be positive."));

    p.parameter_directory =
      std::filesystem::absolute(prm_file).parent_path().string();
    p.run_name = prm.get({"Output"}, "Run name");
    if (p.run_name.empty())
      p.run_name = std::filesystem::path(prm_file).stem().string();
    AssertThrow(p.run_name.find('/') == std::string::npos,
                dealii::ExcMessage("Output / Run name must not contain '/'."));
    p.output_directory =
      (std::filesystem::path(prm.get({"Output"}, "Directory")) / p.run_name)
        .lexically_normal()
        .string();
    p.field_output_interval =
      prm.get_integer({"Output"}, "Field output interval");
    p.checkpoint_interval = prm.get_integer({"Output"}, "Checkpoint interval");
    p.checkpoint_minutes =
      prm.get_double({"Output"}, "Checkpoint wall time interval");
    p.resume         = prm.get_bool({"Output"}, "Resume");
    p.parameter_file = std::filesystem::absolute(prm_file).string();
    p.progress       = prm.get({"Output"}, "Progress");
    p.solver_log     = prm.get({"Output"}, "Solver log");
    parse_entries(prm, {"Output"}, test_hooks(), p);

    p.polynomial_degree =
      prm.get_integer({"Discretization"}, "Polynomial degree");
    p.mapping_degree = prm.get_integer({"Discretization"}, "Mapping degree");
    return p;
  }
} // namespace systole
