#pragma once

#include <string>

class vtkObject;
class vtkFieldData;

namespace systole::Geometry
{
  /// A vtkCallbackCommand callback for VTK's ErrorEvent and WarningEvent: it
  /// appends the message text (trailing blanks dropped, "; " between
  /// messages) to the std::string that @p client_data points to, so that a
  /// failed read of a VTK file becomes one error line instead of VTK's own
  /// console output.
  void
  collect_vtk_message(vtkObject    *caller,
                      unsigned long event,
                      void         *client_data,
                      void         *call_data);

  /// The names of the arrays of @p data for a message: 'a', 'b', ... ('' for
  /// an unnamed array; empty without arrays).
  std::string
  vtk_array_names(vtkFieldData &data);
} // namespace systole::Geometry
