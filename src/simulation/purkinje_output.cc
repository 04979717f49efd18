#include "simulation/purkinje_output.h"

#include <filesystem>
#include <fstream>
#include <iomanip>

namespace systole
{
  namespace
  {
    void
    write_xdmf(const std::string                        &path,
               const Electrophysiology::PurkinjeNetwork &network)
    {
      std::ofstream out(path);
      out << std::setprecision(17);
      const auto n = network.nodes.size(), m = network.edges.size();
      out << "<?xml version=\"1.0\" ?>\n"
          << "<Xdmf Version=\"3.0\">\n  <Domain>\n"
          << "    <Grid Name=\"purkinje\" GridType=\"Uniform\">\n"
          << "      <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
          << "NumberOfElements=\"" << m << "\">\n"
          << "        <DataItem Dimensions=\"" << m
          << " 2\" NumberType=\"Int\" Format=\"XML\">\n";
      for (const auto &[a, b] : network.edges)
        out << "          " << a << ' ' << b << '\n';
      out << "        </DataItem>\n      </Topology>\n"
          << "      <Geometry GeometryType=\"XYZ\">\n"
          << "        <DataItem Dimensions=\"" << n
          << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">\n";
      for (const auto &x : network.nodes)
        out << "          " << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
      out << "        </DataItem>\n      </Geometry>\n"
          << "      <Attribute Name=\"activation_time\" AttributeType="
          << "\"Scalar\" Center=\"Node\">\n"
          << "        <DataItem Dimensions=\"" << n
          << "\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">\n";
      for (const double t : network.times)
        out << "          " << t << '\n';
      out << "        </DataItem>\n      </Attribute>\n"
          << "    </Grid>\n  </Domain>\n</Xdmf>\n";
    }
  } // namespace


  void
  write_purkinje(IO::ResultsFile                          &results,
                 const Electrophysiology::PurkinjeNetwork &network,
                 const MPI_Comm                            comm)
  {
    if (network.empty())
      return;
    IO::TableColumn x{"x", "mm", {}, {}}, y{"y", "mm", {}, {}},
      z{"z", "mm", {}, {}}, time{"activation_time", "ms", network.times, {}},
      junction{"junction", "-", {}, {}};
    for (const auto &p : network.nodes)
      {
        x.values.push_back(p[0]);
        y.values.push_back(p[1]);
        z.values.push_back(p[2]);
      }
    junction.values.assign(network.nodes.size(), 0.0);
    for (const unsigned int j : network.junctions)
      junction.values[j] = 1;
    results.write_table("purkinje/nodes", {x, y, z, time, junction});
    IO::TableColumn parent{"parent", "-", {}, {}}, child{"child", "-", {}, {}};
    for (const auto &[a, b] : network.edges)
      {
        parent.values.push_back(a);
        child.values.push_back(b);
      }
    results.write_table("purkinje/edges", {parent, child});
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      write_xdmf((std::filesystem::path(results.path()).parent_path() /
                  "purkinje.xdmf")
                   .string(),
                 network);
  }
} // namespace systole
