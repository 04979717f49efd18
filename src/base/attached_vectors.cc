#include "base/attached_vectors.h"

namespace systole
{
  void
  AttachedVectors::attach(const dealii::DoFHandler<3> &dof_handler,
                          const dealii::IndexSet      &relevant,
                          const std::vector<const LA::MPI::Vector *> &sources)
  {
    vectors.resize(sources.size());
    std::vector<const LA::MPI::Vector *> in;
    for (unsigned int i = 0; i < sources.size(); ++i)
      {
        // Assigning an owned vector fills the ghosts (deal.II 9.4, PETSc).
        vectors[i].reinit(sources[i]->locally_owned_elements(),
                          relevant,
                          dof_handler.get_communicator());
        vectors[i] = *sources[i];
        in.push_back(&vectors[i]);
      }
    transfer = std::make_unique<
      dealii::parallel::distributed::SolutionTransfer<3, LA::MPI::Vector>>(
      dof_handler);
    transfer->prepare_for_serialization(in);
  }


  void
  AttachedVectors::clear()
  {
    transfer.reset();
    vectors.clear();
  }


  std::vector<LA::MPI::Vector>
  read_attached_vectors(const dealii::DoFHandler<3> &dof_handler,
                        const dealii::IndexSet      &owned,
                        const unsigned int           n)
  {
    std::vector<LA::MPI::Vector>   out(n);
    std::vector<LA::MPI::Vector *> pointers;
    for (auto &v : out)
      {
        v.reinit(owned, dof_handler.get_communicator());
        pointers.push_back(&v);
      }
    dealii::parallel::distributed::SolutionTransfer<3, LA::MPI::Vector>
      transfer(dof_handler);
    transfer.deserialize(pointers);
    return out;
  }
} // namespace systole
