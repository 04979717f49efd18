"""Post-processing of Systole results files (HDF5 written by the C++ code).

Modules:

- :mod:`systole_post.results`: :func:`read_results` reads a results file into a
  :class:`Results` object.
- :mod:`systole_post.compare`: compares time-series columns with a reference CSV
  under per-column tolerances (used by the ``run`` tests) and writes reference CSVs.
- :mod:`systole_post.plot`: plots time-series columns against time into a PNG.
- :mod:`systole_post.fibres`: plots the helix-angle profile written by ``systole-fibres``.
- :mod:`systole_post.bullseye`: AHA 17-segment bull's-eye plots of the "AHA segments"
  postprocessor's /summary columns.
- :mod:`systole_post.study`: ``systole-study``: designed parameter studies of a base .prm,
  run N at a time and resumable, gathered into one table.
- :mod:`systole_post.sensitivity`: Gaussian-process emulator and Sobol indices of a study.
- :mod:`systole_post.pvpython`: finds pvpython (the set-up unpacks Debian's) and runs a script
  in it under xvfb-run.
"""

from systole_post.results import Results, ResultsError, read_results

__all__ = ["Results", "ResultsError", "read_results"]
