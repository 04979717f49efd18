#include "simulation/circulation_columns.h"

#include "base/units.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole
{
  void
  append_model_columns(const Circulation::Model              &model,
                       const Circulation::Arguments          &a,
                       const std::vector<Circulation::Phase> &phases,
                       std::vector<IO::Column>               &row)
  {
    using namespace Circulation;
    dealii::Vector<double> outputs;
    model.evaluate_outputs(a, outputs);
    for (unsigned int i = 0; i < model.n_states(); ++i)
      {
        const auto &s = model.states()[i];
        row.push_back({s.name + output_suffix(s.quantity),
                       output_unit(s.quantity),
                       to_output_unit(s.quantity, a.y[i])});
      }
    for (unsigned int i = 0; i < model.outputs().size(); ++i)
      {
        const auto &o = model.outputs()[i];
        row.push_back({o.name + output_suffix(o.quantity),
                       output_unit(o.quantity),
                       to_output_unit(o.quantity, outputs[i])});
      }
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      row.push_back({model.cavities()[c].name + "_phase",
                     "-",
                     static_cast<double>(code(phases[c]))});
    row.push_back({"total_blood_volume_mL",
                   "mL",
                   Units::mm3_to_mL(model.total_blood_volume(a.y))});
  }


  std::vector<IO::Column>
  valve_event_columns(const Circulation::Model &model, const ValveEventRow &e)
  {
    std::vector<IO::Column> row = {{"time", "ms", e.time},
                                   {"beat", "-", static_cast<double>(e.beat)},
                                   {"valve", "-", static_cast<double>(e.valve)},
                                   {"opens", "-", e.opens ? 1.0 : 0.0}};
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      {
        const auto &cavity = model.cavities()[c];
        row.push_back({cavity.name + "_volume_mL",
                       "mL",
                       Units::mm3_to_mL(e.y[cavity.volume_state])});
        row.push_back({cavity.name + "_pressure_mmHg",
                       "mmHg",
                       Units::kPa_to_mmHg(e.cavity_pressures[c])});
      }
    return row;
  }


  double
  summary_value(const std::vector<Circulation::SummaryColumn> &row,
                const std::string                             &name)
  {
    for (const auto &c : row)
      if (c.name == name)
        return c.value;
    return std::numeric_limits<double>::quiet_NaN();
  }


  std::string
  beat_log_line(const Circulation::Model                      &model,
                const unsigned int                             beat,
                const std::vector<Circulation::SummaryColumn> &summary)
  {
    std::ostringstream o;
    o << std::fixed << std::setprecision(1) << "Beat " << beat << ":";
    // One cavity per line after the first (the closed loop has four), so
    // that no line exceeds 100 columns.
    for (const auto &cavity : model.cavities())
      {
        const std::string n = cavity.name + "_";
        o << (&cavity == &model.cavities().front() ? " " : "\n  ")
          << cavity.name << " EDV " << summary_value(summary, n + "EDV_mL")
          << " mL, ESV " << summary_value(summary, n + "ESV_mL") << " mL, EF "
          << summary_value(summary, n + "EF") << " %, peak "
          << summary_value(summary, n + "peak_pressure_mmHg") << " mmHg;";
      }
    o << (model.cavities().size() > 1 ? "\n  " : " ") << "EDV change "
      << std::defaultfloat << std::setprecision(2)
      << 100 * summary_value(summary, "EDV_change") << " %";
    const double sv_difference = summary_value(summary, "SV_difference");
    if (!std::isnan(sv_difference))
      o << ", stroke volumes " << 100 * sv_difference << " % apart";
    return o.str();
  }
} // namespace systole
