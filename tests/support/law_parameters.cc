#include "support/law_parameters.h"

namespace test_support
{
  systole::Materials::HolzapfelOgden::Parameters
  transversely_isotropic_holzapfel_ogden()
  {
    systole::Materials::HolzapfelOgden::Parameters p;
    p.a_s  = 0.0;
    p.a_fs = 0.0;
    return p;
  }
} // namespace test_support
