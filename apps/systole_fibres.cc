// systole-fibres: build the mesh and fibre field of a parameter file and write
// them (fibre vectors for ParaView, helix angle through the wall).
#include <deal.II/base/mpi.h>

#include "base/errors.h"
#include "simulation/fibre_inspection.h"
#include "simulation/simulation.h"

#include <iostream>
#include <string>

namespace
{
  const char *usage =
    "Usage: systole-fibres PARAMETER_FILE.prm   write the fibre field the file describes\n"
    "       systole-fibres --help | --version\n"
    "Reads the same file as systole (subsections Geometry, Fibres, Output, Discretization)\n"
    "and writes <Output/Directory>/<run name>/results.h5 (+ fields.xdmf for ParaView):\n"
    "fibre, sheet and sheet_normal at the vertices of every cell, and on LV meshes the\n"
    "helix angle against transmural depth as the /summary table\n"
    "(plot it with scripts/plot_fibres.py RESULTS.h5 -o OUT.png).\n";
} // namespace

int
main(int argc, char *argv[])
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;

  const std::string first = argc > 1 ? argv[1] : "";
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
  if (first.rfind("-", 0) == 0 || argc > 2)
    {
      if (root)
        std::cerr << "systole-fibres: unknown arguments.\n" << usage;
      return 1;
    }
  try
    {
      systole::inspect_fibres(first, comm, std::cout);
    }
  catch (const std::exception &e)
    {
      // Input errors occur on every rank alike: rank 0 prints one line.
      if (root)
        std::cerr << "systole-fibres: error: " << systole::one_line_message(e)
                  << std::endl;
      return 1;
    }
  return 0;
}
