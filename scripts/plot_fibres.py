#!/usr/bin/env python3
"""Plot the helix angle through the wall from a systole-fibres results file into a PNG.

    plot_fibres.py RESULTS.h5 [-o OUT.png]

Default output: helix_angle.png next to the results file. Prints the path written.
"""

import argparse
import sys
from pathlib import Path

from systole_post.fibres import plot_helix_profile
from systole_post.results import ResultsError


def main(argv=None) -> int:
    """Parse the command line, write the plot, return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="results file of systole-fibres (HDF5)")
    parser.add_argument("-o", "--output", type=Path,
                        help="PNG to write (default: helix_angle.png next to RESULTS)")
    args = parser.parse_args(argv)
    output = args.output or args.results.parent / "helix_angle.png"
    try:
        written = plot_helix_profile(args.results, output)
    except (ResultsError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    print(written)
    return 0


if __name__ == "__main__":
    sys.exit(main())
