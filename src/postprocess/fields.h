#pragma once

#include "postprocess/postprocessor.h"

#include <functional>

namespace systole::Postprocess
{
  /// A postprocessor that writes fields only: each a function of the
  /// PointQuantities of a point ("fibre stretch", "active tension",
  /// "stress", "strain", "volume ratio" of the factory table).
  class Fields : public Postprocessor
  {
  public:
    using Getter = std::function<double(const PointQuantities &)>;

    /// @p fields: (name, value) of each field; @p needs_frame: the values
    /// use the cardiac frame.
    Fields(std::vector<std::pair<std::string, Getter>> fields,
           const bool                                  needs_frame);

    Needs
    needs() const override;

    std::vector<std::string>
    field_names() const override;

    double
    field_value(const unsigned int i, const PointQuantities &q) const override;

  private:
    std::vector<std::pair<std::string, Getter>> fields;
    bool                                        needs_frame;
  };
} // namespace systole::Postprocess
