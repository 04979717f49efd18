#include "base/interrupt.h"

#include <csignal>

namespace systole
{
  namespace
  {
    volatile std::sig_atomic_t signal_received = 0;

    extern "C" void
    on_signal(int signal)
    {
      signal_received = signal;
    }
  } // namespace

  void
  install_interrupt_handlers()
  {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
  }

  bool
  interrupted(const MPI_Comm comm)
  {
    const unsigned int local = signal_received != 0 ? 1 : 0;
    return dealii::Utilities::MPI::max(local, comm) > 0;
  }
} // namespace systole
