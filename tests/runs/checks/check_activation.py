#!/usr/bin/env python3
"""Check an electrophysiology results file: activation summary and time series.

    check_activation.py RESULTS.h5 [NAME=VALUE:TOL ...] [--increasing A,B,...]
                        [--plateau T0:DIP] [--serial SERIAL.h5]
                        [--closer-than OTHER.h5] [--ecg]

- every time-series value is finite, the activated fraction lies in [0, 1] and never
  decreases, and the whole volume ends activated;
- each /summary column NAME (last row) lies within TOL of VALUE (an independent value,
  e.g. from the refinement table of docs/verification.md);
- --increasing: the listed /summary columns increase strictly in that order (activation
  times of points ever farther from the stimulus);
- --plateau T0:DIP: in the fields (every node, at every field output), from T0 [ms] on
  (when every node has activated and is on its plateau) no node's potential dips by more
  than DIP [mV] below both its samples before and after; on the plateau the potential
  falls slowly and smoothly, so a dip is a numerical oscillation of the node (an
  unstable explicit step of its ionic current), which a dip below the activation
  threshold would count as a second upstroke;
- --closer-than: each checked /summary column NAME lies closer to its VALUE than OTHER's
  (e.g. another discretization of the same problem at the same mesh size);
- --ecg: the 12 ECG leads are written and obey Einthoven's law (I + III = II) and
  aVR + aVL + aVF = 0 at every row; the QRS spans the activation: it starts no later
  than the first upstroke (the stimulus before it deflects the ECG already) and within a
  sample of the first stimulus' start, and ends within 3 ms plus a sample after the last
  upstroke (the last cells' upstrokes to the plateau: the pseudo-ECG is zero before the
  first and nearly so after the last upstroke, on a flat plateau), the T wave ends
  after it, and V1 ... V6 have an R wave;
- --serial: every time-series and /summary column equals the serial run's to 1e-8
  relative (to the column's scale) plus 1e-10, except the iteration counts of the
  iterative solver, which depend on the partition.
"""

import sys

import h5py
import numpy as np

NOT_COMPARED = ("linear_iterations",)


def table(f, group):
    return {k: np.asarray(f[group][k][()], dtype=float) for k in f[group]} if group in f else {}


def read(path):
    with h5py.File(path, "r") as f:
        return table(f, "timeseries"), table(f, "summary")


def plateau_dips(path, start, allowed, failures):
    with h5py.File(path, "r") as f:
        fields = f["fields"]
        steps = sorted(fields, key=lambda name: int(name.split("_")[-1]))
        times = np.array([float(np.ravel(fields[s].attrs["time"])[0]) for s in steps])
        keep = [s for s, t in zip(steps, times) if t >= start]
        if len(keep) < 3:
            failures.append(f"--plateau: fewer than 3 field outputs from {start} ms on")
            return
        v = np.array([fields[s]["transmembrane_potential"][()].ravel() for s in keep])
        nodes = f["mesh/nodes"][()]
    dip = np.minimum(v[:-2], v[2:]) - v[1:-1]
    worst = np.unravel_index(np.argmax(dip), dip.shape)
    largest = dip[worst]
    at = times[len(times) - len(keep) + 1 + worst[0]]
    print(f"largest plateau dip from {start} ms on: {largest:.3f} mV at {at:.1f} ms, "
          f"node at {np.round(nodes[worst[1]], 3).tolist()}")
    if not largest <= allowed:
        failures.append(f"the potential dips by {largest:.3g} mV on the plateau "
                        f"(at {at:.1f} ms; allowed {allowed} mV)")


def compare(name, values, reference, failures):
    if len(values) != len(reference):
        failures.append(f"{name}: {len(values)} rows, serial run {len(reference)}")
        return
    allowed = 1e-8 * np.nanmax(np.abs(reference)) + 1e-10
    if not np.array_equal(np.isnan(values), np.isnan(reference)):
        failures.append(f"{name}: NaN where the serial run has none (or vice versa)")
        return
    diff = np.nanmax(np.abs(values - reference)) if np.any(np.isfinite(values)) else 0.0
    if not diff <= allowed:
        failures.append(f"{name} differs from the serial run by {diff:.3g}")


LEADS = ["I", "II", "III", "aVR", "aVL", "aVF", "V1", "V2", "V3", "V4", "V5", "V6"]


def check_ecg(ts, summary, failures):
    missing = [lead for lead in LEADS if f"ecg_{lead}" not in ts]
    if missing:
        failures.append("no ECG columns " + ", ".join(missing))
        return
    lead = {name: ts[f"ecg_{name}"] for name in LEADS}
    scale = max(np.max(np.abs(v)) for v in lead.values())
    einthoven = np.max(np.abs(lead["I"] + lead["III"] - lead["II"]))
    goldberger = np.max(np.abs(lead["aVR"] + lead["aVL"] + lead["aVF"]))
    print(f"ECG: largest |lead| {scale:.4g} mV, |I + III - II| <= {einthoven:.2g}, "
          f"|aVR + aVL + aVF| <= {goldberger:.2g}")
    if not (einthoven <= 1e-12 * scale and goldberger <= 1e-12 * scale):
        failures.append("the leads break Einthoven's law or aVR + aVL + aVF = 0")
    dt = np.max(np.diff(ts["time"]))
    qrs, total = summary["ecg_QRS_duration"][-1], summary["total_activation_time"][-1]
    onset = summary["ecg_QRS_onset"][-1]
    first, last = summary["first_activation_time"][-1], summary["last_activation_time"][-1]
    qt = summary["ecg_QT_interval"][-1]
    end = onset + qrs
    print(f"ECG: QRS {qrs:.2f} ms ({onset:.2f} to {end:.2f}), total activation "
          f"{total:.2f} ms ({first:.2f} to {last:.2f}), QT {qt:.1f} ms")
    if not (onset <= first and onset <= dt):
        failures.append(f"the QRS starts at {onset:.2f} ms: not within a sample of "
                        f"the stimulus at 0 and before the first upstroke at {first:.2f} ms")
    if not 0 <= end - last <= 3.0 + dt:
        failures.append(f"the QRS ends at {end:.2f} ms: not within 0 ... {3 + dt} ms "
                        f"after the last upstroke at {last:.2f} ms")
    if not qt > qrs:
        failures.append(f"QT {qt} ms is not longer than the QRS")
    for v in ("V1", "V2", "V3", "V4", "V5", "V6"):
        if not summary[f"ecg_R_amplitude_{v}"][-1] > 0:
            failures.append(f"no R wave in {v}")


def main(argv) -> int:
    args = argv[1:]
    ecg = "--ecg" in args
    if ecg:
        args.remove("--ecg")
    serial, increasing = None, []
    if "--serial" in args:
        i = args.index("--serial")
        serial = args[i + 1]
        del args[i : i + 2]
    closer_than = None
    if "--closer-than" in args:
        i = args.index("--closer-than")
        closer_than = read(args[i + 1])[1]
        del args[i : i + 2]
    plateau = None
    if "--plateau" in args:
        i = args.index("--plateau")
        plateau = [float(x) for x in args[i + 1].split(":")]
        del args[i : i + 2]
    if "--increasing" in args:
        i = args.index("--increasing")
        increasing = args[i + 1].split(",")
        del args[i : i + 2]
    ts, summary = read(args[0])
    failures = []
    for name, values in ts.items():
        if not np.all(np.isfinite(values)):
            failures.append(f"time-series column {name} has non-finite values")
    fraction = ts["activated_fraction"]
    if np.any(fraction < 0) or np.any(fraction > 1) or np.any(np.diff(fraction) < 0):
        failures.append("the activated fraction leaves [0, 1] or decreases")
    if summary["activated_fraction"][-1] != 1.0:
        failures.append(f"only {summary['activated_fraction'][-1]:.4f} of the volume activated")
    for spec in args[1:]:
        name, rest = spec.split("=")
        value, tolerance = (float(x) for x in rest.split(":"))
        got = summary[name][-1]
        status = "ok" if abs(got - value) <= tolerance else "FAIL"
        print(f"{name}: {got:.4f} (expected {value} +- {tolerance}) {status}")
        if status != "ok":
            failures.append(f"{name} = {got} is not within {tolerance} of {value}")
        if closer_than is not None:
            other = closer_than[name][-1]
            print(f"{name}: the other run's {other:.4f}")
            if not abs(got - value) < abs(other - value):
                failures.append(f"{name} = {got} is not closer to {value} than the other "
                                f"run's {other}")
    times = [summary[name][-1] for name in increasing]
    print("increasing: " + ", ".join(f"{n} {t:.3f}" for n, t in zip(increasing, times)))
    if any(not b > a for a, b in zip(times, times[1:])):
        failures.append("activation times do not increase along " + ", ".join(increasing))
    if ecg:
        check_ecg(ts, summary, failures)
    if plateau is not None:
        plateau_dips(args[0], plateau[0], plateau[1], failures)
    if serial is not None:
        serial_ts, serial_summary = read(serial)
        for group, ours, theirs in (("time series", ts, serial_ts),
                                    ("summary", summary, serial_summary)):
            for name, values in ours.items():
                if name not in NOT_COMPARED:
                    compare(f"{group} {name}", values, theirs[name], failures)
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
