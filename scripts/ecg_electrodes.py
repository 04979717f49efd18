#!/usr/bin/env python3
"""Print the 'ECG electrodes' entry for a heart model placed in an adult torso.

    ecg_electrodes.py [--centre X Y Z] [--right-angle DEG]

The nine electrodes at their standard positions on the torso (body frame: x to the
patient's left, y anterior, z superior, origin at the heart's centre, mm; V1, V2 in the
4th intercostal space beside the sternum, V4 5th space midclavicular, V3 between, V5
anterior and V6 mid-axillary line at V4's level, the limb electrodes where the limbs
join the torso), mapped into the model's coordinates. The model's long axis is z (base
up, apex down); in the body the base-to-apex axis points left, anterior and inferior,
a = (cos 45 cos 30, sin 30, -sin 45 cos 30) (45 degrees below the horizontal in the
frontal plane, tilted 30 degrees forwards); the model's -z is a, its +x the body
direction that lies RIGHT-ANGLE degrees from anterior towards the patient's right in
the transverse plane, projected normal to a, and the model point CENTRE is the body's
origin. Defaults (centre 0 0 -40, angle 0) give the default electrodes of
Electrophysiology / ECG electrodes (the LV of parameters/lv_heartbeat.prm, its septal
side +x facing forwards). For the biventricular mesh (RV towards +x) use the angle 45:
the septum faces right and forwards, as in the body (LAO 45 degrees looks along it).
"""

import argparse
import sys

import numpy as np

BODY = {
    "RA": (-230, 0, 180), "LA": (170, 0, 180), "LL": (30, 0, -350),
    "V1": (-55, 85, 20), "V2": (-5, 90, 20), "V3": (20, 88, 0), "V4": (45, 80, -20),
    "V5": (95, 45, -20), "V6": (120, -10, -20),
}


def model_frame(right_angle: float) -> np.ndarray:
    """Rows: the model's x, y, z axes in body coordinates.

    The body frame (left, anterior, superior) is left-handed, the model's frame right-handed:
    the model's y is z x x in space, which in body coordinates is ex x ez (not ez x ex,
    which would place the mirror image of the heart: a left-handed helix of the fibres
    turned right-handed and the model's +y on the wrong side). So the matrix has
    determinant -1 in these coordinates."""
    d = np.radians
    a = np.array([np.cos(d(45)) * np.cos(d(30)), np.sin(d(30)),
                  -np.sin(d(45)) * np.cos(d(30))])
    towards = np.array([-np.sin(d(right_angle)), np.cos(d(right_angle)), 0.0])
    ex = towards - (towards @ a) * a
    ex /= np.linalg.norm(ex)
    ez = -a
    return np.array([ex, np.cross(ex, ez), ez])


def electrodes(centre, right_angle: float) -> dict[str, np.ndarray]:
    """The model coordinates [mm] of the nine electrodes."""
    frame = model_frame(right_angle)
    return {name: frame @ np.array(p, float) + np.asarray(centre, float)
            for name, p in BODY.items()}


def main(argv=None) -> int:
    """Print the entry."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--centre", type=float, nargs=3, default=(0.0, 0.0, -40.0),
                        metavar=("X", "Y", "Z"),
                        help="model point at the heart's centre [mm] (default 0 0 -40)")
    parser.add_argument("--right-angle", type=float, default=0.0,
                        help="angle of the model's +x from anterior towards the right "
                             "[degrees] (default 0)")
    args = parser.parse_args(argv)
    e = electrodes(args.centre, args.right_angle)
    order = ["V1", "V2", "V3", "V4", "V5", "V6", "RA", "LA", "LL"]
    print("; ".join(f"{n}: " + " ".join(f"{v:.0f}" for v in e[n]) for n in order))
    return 0


if __name__ == "__main__":
    sys.exit(main())
