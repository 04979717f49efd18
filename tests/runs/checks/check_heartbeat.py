#!/usr/bin/env python3
"""Check a heartbeat results file against conservation laws and the phase logic.

    check_heartbeat.py RESULTS.h5 [--serial SERIAL.h5] [--activation EP.h5]

- every beat passes the phases in the order 0 -> 1 -> 2 -> 3 -> 0 (events table);
- during the isovolumetric phases (1 and 3) the cavity volume of the deformed mesh stays at
  the volume of the phase's start to 1e-8 relative;
- over each ejection, the integrated aortic outflow equals the volume lost by the deformed
  mesh to 1e-6 relative (and over each filling, the mitral inflow the volume gained);
- with --serial, the valve events and the beat summaries agree with the serial run (event
  times to 0.05 ms, summary values to 1e-4 relative): 2 ranks reproduce 1 rank;
- with --activation (an electromechanical beat), the first beat's 90 % and total activation
  times equal those of the electrophysiology problem alone on the same EP mesh (EP.h5) to
  1e-6 relative, the last field step holds an activation map with every node activated and
  no time after that run's last upstroke, and the mitral valve closes after the first
  upstroke.
"""

import sys

import h5py
import numpy as np


def table(f, group):
    return {k: f[group][k][()] for k in f[group]} if group in f else {}


def main(argv) -> int:
    args = argv[1:]
    serial = None
    if "--serial" in args:
        i = args.index("--serial")
        serial = args[i + 1]
        del args[i : i + 2]
    activation = None
    if "--activation" in args:
        i = args.index("--activation")
        activation = args[i + 1]
        del args[i : i + 2]
    failures = []
    with h5py.File(args[0], "r") as f:
        ts, events, summary = table(f, "timeseries"), table(f, "events"), table(f, "summary")
    n = min(len(v) for v in ts.values())
    ts = {k: v[:n] for k, v in ts.items()}

    # Phase order.
    expected_next = {0: 1, 1: 2, 2: 3, 3: 0}
    for frm, to, t in zip(events["from_phase"], events["to_phase"], events["time"]):
        if expected_next[int(frm)] != int(to):
            failures.append(f"transition {int(frm)} -> {int(to)} at t = {t:.2f} ms")
    print(f"{len(events['time'])} valve events, {len(summary.get('beat', []))} beat(s)")
    if len(events["time"]) < 4:
        failures.append("fewer than one full cycle of valve events")

    # Rows: the phase column is the phase of the step that ends at the row; a transition
    # row closes the old phase.
    phase = ts["phase"].astype(int)
    volume = ts["mechanics_volume_mL"]
    outflow = ts["cumulative_outflow_mL"]
    inflow = ts["cumulative_inflow_mL"]
    worst_iso, worst_flow = 0.0, 0.0
    start = 0
    for i in range(1, n + 1):
        if i < n and phase[i] == phase[start + 1 if start + 1 < n else start]:
            continue
        # segment of steps start+1 .. i-1 with one phase; row `start` is its beginning
        seg = slice(start, i)
        p = phase[min(start + 1, n - 1)]
        v = volume[seg]
        if p in (1, 3):
            worst_iso = max(worst_iso, np.max(np.abs(v - v[0])) / v[0])
        elif p == 2:
            lost = v[0] - v[-1]
            out = outflow[i - 1] - outflow[start]
            if lost > 0:
                worst_flow = max(worst_flow, abs(out - lost) / lost)
        elif p == 0 and i - start > 1:
            gained = v[-1] - v[0]
            into = inflow[i - 1] - inflow[start]
            if abs(gained) > 1e-3:
                worst_flow = max(worst_flow, abs(into - gained) / abs(gained))
        start = i - 1
        if i == n:
            break
    print(f"isovolumetric volume drift {worst_iso:.2e} (limit 1e-8); "
          f"flow balance {worst_flow:.2e} (limit 1e-6)")
    if not worst_iso <= 1e-8:
        failures.append(f"isovolumetric volume drift {worst_iso:.3e} > 1e-8")
    if not worst_flow <= 1e-6:
        failures.append(f"integrated flow differs from the volume change by {worst_flow:.3e}")

    if serial:
        with h5py.File(serial, "r") as f:
            ev1, sum1 = table(f, "events"), table(f, "summary")
        if len(ev1["time"]) != len(events["time"]):
            failures.append("a different number of valve events than the serial run")
        else:
            dt = np.max(np.abs(ev1["time"] - events["time"]))
            print(f"event times vs serial: max difference {dt:.2e} ms")
            if not dt <= 0.05:
                failures.append(f"event times differ from the serial run by {dt} ms")
        for key in ("EDV_mL", "ESV_mL", "peak_pressure_mmHg", "stroke_work_mmHg_mL"):
            a, b = sum1.get(key), summary.get(key)
            if a is None or b is None or len(a) != len(b):
                failures.append(f"summary {key} missing or of different length")
                continue
            rel = np.nanmax(np.abs(a - b) / np.maximum(np.abs(a), 1e-300))
            print(f"summary {key} vs serial: {rel:.2e}")
            if not rel <= 1e-4:
                failures.append(f"summary {key} differs from the serial run by {rel:.2e}")

    if activation:
        failures += check_activation(args[0], summary, events, activation)

    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


def check_activation(path, summary, events, reference_path):
    """An electromechanical beat: the first beat's activation equals that of the
    electrophysiology problem alone on the same EP mesh (one-way coupling), the activation
    map is among the fields, and the mitral valve closes only after the wave started."""
    failures = []
    with h5py.File(reference_path, "r") as f:
        reference = table(f, "summary")
    for key in ("activation_time_90", "total_activation_time"):
        ours, theirs = summary.get(key), reference.get(key)
        if ours is None or theirs is None:
            failures.append(f"summary {key} missing")
            continue
        diff = abs(ours[0] - theirs[-1])
        print(f"beat 0 {key} {ours[0]:.4f} ms, electrophysiology alone {theirs[-1]:.4f} ms")
        if not diff <= 1e-6 * abs(theirs[-1]) + 1e-9:
            failures.append(f"{key} differs from the electrophysiology alone by {diff:.3g} ms")
    with h5py.File(path, "r") as f:
        steps = sorted(f["fields"]) if "fields" in f else []
        if not steps:
            failures.append("no fields written")
        else:
            last = f["fields"][steps[-1]]
            if "activation_time" not in last:
                failures.append("no activation_time field")
            else:
                times = np.asarray(last["activation_time"][()], dtype=float)
                print(f"activation_time field: {np.isfinite(times).mean():.3f} of the nodes "
                      f"activated, {np.nanmin(times):.2f} to {np.nanmax(times):.2f} ms")
                if not np.all(np.isfinite(times)):
                    failures.append("nodes without activation time at the end of the run")
                elif not np.nanmax(times) <= reference["last_activation_time"][-1] + 1e-6:
                    failures.append("the activation map holds times after the last upstroke "
                                    "of the electrophysiology alone")
    closing = events["time"][(events["from_phase"] == 0) & (events["to_phase"] == 1)]
    first = reference["first_activation_time"][-1]
    if len(closing) and not closing[0] > first:
        failures.append(f"the mitral valve closed at {closing[0]} ms, before the first "
                        f"upstroke at {first} ms")
    return failures


if __name__ == "__main__":
    sys.exit(main(sys.argv))
