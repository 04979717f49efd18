// systole: run a cardiac simulation described by a parameter file.
#include <deal.II/base/mpi.h>

#include "base/errors.h"
#include "io/results_file.h"
#include "simulation/simulation.h"

#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
  const char *usage =
    "Usage: systole PARAMETER_FILE.prm       run the simulation the file describes\n"
    "       systole --print-parameters [FILE] print every parameter with its documentation\n"
    "                                         (defaults, or the values FILE sets)\n"
    "       systole --print-parameters-json [FILE]  the same as JSON, with each\n"
    "                                         entry's pattern (type and bounds)\n"
    "       systole --check FILE             read and validate FILE, run nothing\n"
    "       systole --resume results/RUN     continue a heartbeat from its newest valid checkpoint\n"
    "       systole --help | --version\n"
    "Run in parallel with: mpirun -np N systole FILE.prm\n"
    "Results: <Output/Directory>/<run name>/results.h5 (+ fields.xdmf for ParaView).\n"
    "Units inside: mm, ms, kPa (pressures in mmHg and volumes in mL only where so named).\n";
} // namespace

int
main(int argc, char *argv[])
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;

  const std::string first = argc > 1 ? argv[1] : "";
  try
    {
      if (argc < 2 || first == "--help" || first == "-h")
        {
          if (root)
            std::cout << usage;
          return argc < 2 ? 1 : 0;
        }
      if (first == "--version")
        {
          if (root)
            std::cout << systole::version() << std::endl;
          return 0;
        }
      if (first == "--print-parameters")
        {
          if (root)
            systole::print_parameters(std::cout, argc > 2 ? argv[2] : "");
          return 0;
        }
      if (first == "--print-parameters-json")
        {
          if (root)
            systole::print_parameters(std::cout,
                                      argc > 2 ? argv[2] : "",
                                      /*json=*/true);
          return 0;
        }
      if (first == "--check" && argc == 3)
        {
          systole::Simulation simulation(argv[2], comm, std::cout);
          if (root)
            std::cout << argv[2] << ": ok" << std::endl;
          return 0;
        }
      if (first == "--resume" && argc == 3)
        {
          const std::string file =
            systole::Simulation::parameter_file_of(argv[2]);
          systole::Simulation simulation(file, comm, std::cout, argv[2]);
          simulation.run();
          return 0;
        }
      if (first.rfind("-", 0) == 0 || argc > 2)
        {
          if (root)
            std::cerr << "systole: unknown arguments.\n" << usage;
          return 1;
        }

      systole::Simulation simulation(first, comm, std::cout);
      simulation.run();
    }
  catch (const std::exception &e)
    {
      // Input errors occur on every rank alike: rank 0 prints one line, all
      // exit non-zero.
      if (root)
        std::cerr << "systole: error: " << systole::one_line_message(e)
                  << std::endl;
      // A failed write left the results file open on purpose: end without
      // MPI_Finalize, which would make HDF5 close (and crash on) it.
      if (systole::IO::a_results_write_failed())
        {
          std::cout.flush();
          std::_Exit(1);
        }
      return 1;
    }
  return 0;
}
