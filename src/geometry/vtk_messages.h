#pragma once

class vtkObject;

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
} // namespace systole::Geometry
