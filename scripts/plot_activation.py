#!/usr/bin/env python3
"""Plot the activation map of an electrophysiology results file into a PNG.

    plot_activation.py RESULTS.h5 [-o OUT.png] [--slice z=1.5] [--step N]

A histogram of the activation times and the isochrones on a plane slice (default: the
middle plane normal to z). Default output: activation.png next to the results file.
Prints the path written.
"""

import argparse
import sys
from pathlib import Path

from systole_post.activation import plot_activation
from systole_post.results import ResultsError


def parse_slice(text: str) -> tuple[str, float | None]:
    """'z=1.5' -> ('z', 1.5); 'y' -> ('y', None) (the middle plane)."""
    axis, _, value = text.partition("=")
    if axis not in ("x", "y", "z"):
        raise argparse.ArgumentTypeError(f"slice '{text}': the axis must be x, y or z")
    try:
        return axis, float(value) if value else None
    except ValueError:
        raise argparse.ArgumentTypeError(f"slice '{text}': '{value}' is not a number") from None


def main(argv=None) -> int:
    """Parse the command line, write the plot, return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="results file of the electrophysiology problem")
    parser.add_argument("-o", "--output", type=Path,
                        help="PNG to write (default: activation.png next to RESULTS)")
    parser.add_argument("--slice", type=parse_slice, default=("z", None),
                        help="plane of the picture, AXIS[=VALUE] in mm (default: z, middle)")
    parser.add_argument("--step", type=int, help="field step (default: the last one)")
    args = parser.parse_args(argv)
    output = args.output or args.results.parent / "activation.png"
    try:
        written = plot_activation(args.results, output, *args.slice, step=args.step)
    except (ResultsError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    print(written)
    return 0


if __name__ == "__main__":
    sys.exit(main())
