#!/usr/bin/env python3
"""The unloaded mesh, inflated again by Problem = mechanics, holds the imaged cavity volume.

    check_reload.py MECHANICS.h5 UNLOADING.h5 REL_TOL

The last volume_mL of the mechanics run (the gmsh mesh that the unloading wrote, inflated to
the image pressure) must equal the unloading run's /summary image_volume_mL (the cavity
volume of the synthetic image: the true reference inflated) within REL_TOL.
"""

import sys

from systole_post.results import read_results


def main(argv) -> int:
    reloaded = read_results(argv[1]).timeseries["volume_mL"][-1]
    image = read_results(argv[2]).summary["image_volume_mL"][-1]
    tolerance = float(argv[3])
    error = abs(reloaded - image) / image
    print(f"reloaded volume {reloaded:.6f} mL, image {image:.6f} mL: relative difference "
          f"{error:.3g} (must be <= {tolerance})")
    return 0 if error <= tolerance else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
