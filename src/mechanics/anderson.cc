#include "mechanics/anderson.h"

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <vector>

namespace systole::Mechanics
{
  AndersonAcceleration::AndersonAcceleration(const unsigned int depth,
                                             const double       max_growth)
    : depth(depth)
    , max_growth(max_growth)
  {}

  void
  AndersonAcceleration::reset()
  {
    clear_history();
    have_f    = false;
    have_step = false;
  }

  void
  AndersonAcceleration::clear_history()
  {
    dF.clear();
    dX.clear();
    dG.clear();
    dY.clear();
  }

  void
  AndersonAcceleration::pop_oldest()
  {
    // (The further unknowns' history is kept only aligned with the main
    // one, else not at all.)
    if (dG.size() == dF.size())
      {
        dG.pop_front();
        dY.pop_front();
      }
    else
      {
        dG.clear();
        dY.clear();
      }
    dF.pop_front();
    dX.pop_front();
  }

  void
  AndersonAcceleration::record_step(const LA::MPI::Vector        &step,
                                    const dealii::Vector<double> *g_step)
  {
    if (depth == 0)
      return;
    last_step = step;
    if (g_step != nullptr)
      last_g_step = *g_step;
    have_step = true;
  }

  void
  AndersonAcceleration::push_history(const LA::MPI::Vector        &f,
                                     const dealii::Vector<double> *g)
  {
    LA::MPI::Vector df = f;
    df -= last_f;
    dF.push_back(df);
    dX.push_back(last_step);
    if (g != nullptr && last_g.size() == g->size() &&
        last_g_step.size() == g->size() && dG.size() + 1 == dF.size())
      {
        dealii::Vector<double> dg = *g;
        dg -= last_g;
        dG.push_back(dg);
        dY.push_back(last_g_step);
      }
    else
      {
        dG.clear();
        dY.clear();
      }
    if (dF.size() > depth)
      pop_oldest();
  }

  void
  AndersonAcceleration::accelerate(LA::MPI::Vector        &f,
                                   dealii::Vector<double> *g)
  {
    if (depth == 0)
      return;
    if (have_f && have_step)
      push_history(f, g);
    last_f = f;
    if (g != nullptr)
      last_g = *g;
    have_f    = true;
    have_step = false;
    if (dF.empty())
      return;

    // Least squares min |f - dF gamma| by modified Gram-Schmidt QR of dF.
    // A column (nearly) in the span of the later ones is dropped with the
    // older ones: the oldest differences go first (they describe the map
    // furthest from the iterate).
    for (;;)
      {
        const unsigned int           m = dF.size();
        std::vector<LA::MPI::Vector> Q;
        dealii::FullMatrix<double>   R(m, m);
        bool                         dependent = false;
        // Newest column first, so that a dependent column is an old one.
        for (unsigned int c = 0; c < m && !dependent; ++c)
          {
            LA::MPI::Vector q     = dF[m - 1 - c];
            const double    norm0 = q.l2_norm();
            for (unsigned int j = 0; j < c; ++j)
              {
                R(j, c) = Q[j] * q;
                q.add(-R(j, c), Q[j]);
              }
            R(c, c) = q.l2_norm();
            if (!(R(c, c) > 1e-10 * norm0) || !std::isfinite(R(c, c)))
              {
                // Drop this column and every older one.
                const unsigned int drop = m - c;
                for (unsigned int d = 0; d < drop; ++d)
                  pop_oldest();
                dependent = true;
                break;
              }
            q /= R(c, c);
            Q.push_back(q);
          }
        if (dependent)
          {
            if (dF.empty())
              return;
            continue;
          }
        // R gamma' = Q^T f (gamma' in the newest-first column order).
        const double           plain = f.l2_norm();
        dealii::Vector<double> gamma(m);
        for (unsigned int c = 0; c < m; ++c)
          gamma[c] = Q[c] * f;
        for (unsigned int c = m; c-- > 0;)
          {
            for (unsigned int j = c + 1; j < m; ++j)
              gamma[c] -= R(c, j) * gamma[j];
            gamma[c] /= R(c, c);
          }
        LA::MPI::Vector accelerated = f;
        for (unsigned int c = 0; c < m; ++c)
          {
            const unsigned int i = m - 1 - c;
            accelerated.add(-gamma[c], dX[i], -gamma[c], dF[i]);
          }
        // A step far longer than the plain one extrapolates along a mode
        // the plain iteration barely contracts (secant ratio 1 - 1/growth or
        // worse): on a nonlinear map, far from its fixed point, that
        // extrapolation overshoots. The plain update then, with a fresh
        // history.
        const double length = accelerated.l2_norm();
        if (!(length <= max_growth * plain))
          {
            clear_history();
            return;
          }
        f = accelerated;
        // The further unknowns with the same coefficients (when their
        // history is as long: it was kept with every difference).
        if (g != nullptr && dG.size() == m)
          for (unsigned int c = 0; c < m; ++c)
            {
              const unsigned int i = m - 1 - c;
              g->add(-gamma[c], dY[i]);
              g->add(-gamma[c], dG[i]);
            }
        return;
      }
  }
} // namespace systole::Mechanics
