"""The benchmarks of Systole (`scripts/bench`, scripts/bench.py), one module per group.

- :mod:`systole_bench.core`: a case, running it through the systole app, reading its results
  file into a table row, the common table, writing docs/verification.md.
- :mod:`systole_bench.groups`: the table of groups (the names of `--only`), in the order of
  their sections.
- one module per group (p1, p2, p2_mixed, p3, fibres, heartbeat, biv, badinput, checkpoint,
  ep, land, niederer, inverse, ep_lv, mixed, scaling (also scaling-th), tet, large, arostica,
  laws, circulation, cell, postprocess), each with ``sections(args, workdir)``.
"""
