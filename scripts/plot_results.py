#!/usr/bin/env python3
"""Plot the time series of a Systole results file into a PNG.

    plot_results.py RESULTS.h5 [-o OUT.png] [--columns pressure volume ...]

Default output: timeseries.png next to the results file. Prints the path written.
"""

import argparse
import sys
from pathlib import Path

from systole_post.plot import plot_timeseries
from systole_post.results import ResultsError


def main(argv=None) -> int:
    """Parse the command line, write the plot, return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="results file (HDF5)")
    parser.add_argument("-o", "--output", type=Path,
                        help="PNG to write (default: timeseries.png next to RESULTS)")
    parser.add_argument("--columns", nargs="+", metavar="COLUMN",
                        help="columns to plot (default: all but time and step)")
    args = parser.parse_args(argv)
    output = args.output or args.results.parent / "timeseries.png"
    try:
        written = plot_timeseries(args.results, output, args.columns)
    except (ResultsError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    print(written)
    return 0


if __name__ == "__main__":
    sys.exit(main())
