#!/usr/bin/env python3
"""Check a heartbeat results file against conservation laws and the phase logic.

    check_heartbeat.py RESULTS.h5 [--serial SERIAL.h5] [--activation EP.h5] [--closed]
                       [--cavities c1,c2] [--expect NAME=VALUE:TOL ...]

For every 3D cavity c (a c_mechanics_volume_mL column):
- its phases follow 0 -> 1 -> 2 -> 3 -> 0 (column c_phase);
- the deformed mesh holds the 0D volume state (c_mechanics_volume_mL vs c_volume_mL) to
  5 times the run's Mechanics / Cavity volume tolerance (1e-8 at its default 2e-9) relative
  at every step: the volume constraint of the coupled step;
- during the isovolumetric phases (1 and 3, from the valve event that starts them) the
  cavity volume changes by less than 1e-5 of itself (the closed diode valves leak through
  R_max only: 130 mmHg / 75006 mmHg s/mL over 100 ms is 1.7e-4 mL, 3e-6 of an ESV of 60 mL;
  a lost constraint or an open valve moves millilitres);
- with --cavities (e.g. lv,rv for a biventricular mesh), each of them is a 3D cavity, passes
  through all four phases, and has a PV loop: its volume falls by more than 5 % of its EDV
  and its peak pressure exceeds its end-diastolic pressure by more than 5 mmHg in a beat;
- with --closed (a closed-loop circulation), total_blood_volume_mL stays constant to 1e-8
  relative;
- with --serial, the valve events and the beat summaries agree with the serial run (event
  times to 0.05 ms, c_EDV_mL, c_ESV_mL, peak pressure, stroke work to 1e-4 relative): 2
  ranks reproduce 1 rank;
- with --expect, the last beat's summary column NAME is VALUE within TOL (regression values
  from a time-step and mesh study, docs/verification.md);
- with --activation (an electromechanical beat), the first beat's 90 % and total activation
  times equal those of the electrophysiology problem alone on the same EP mesh (EP.h5) to
  1e-6 relative, the last field step holds an activation map with every node activated and
  no time after that run's last upstroke, and the mitral valve closes after the first
  upstroke.
"""

import re
import sys

import h5py
import numpy as np


def table(f, group):
    return {k: f[group][k][()] for k in f[group]} if group in f else {}


def option(args, name, default=None, many=False):
    """Remove --name VALUE (repeatable with many) from args and return the value(s)."""
    values = []
    while name in args:
        i = args.index(name)
        values.append(args[i + 1])
        del args[i : i + 2]
    if many:
        return values
    return values[-1] if values else default


def cavity_volume_tolerance(f):
    """Mechanics / Cavity volume tolerance of the run (its /parameters; 2e-9, the default,
    in files written before the entry)."""
    text = f["parameters"][()] if "parameters" in f else b""
    text = text.decode() if isinstance(text, bytes) else str(text)
    found = re.search(r"set Cavity volume tolerance\s*=\s*([^\s#]+)", text)
    return float(found.group(1)) if found else 2e-9


def cavities(ts):
    """The 3D cavities: those with a c_mechanics_volume_mL column."""
    return [k[: -len("_mechanics_volume_mL")] for k in ts if k.endswith("_mechanics_volume_mL")]


def main(argv) -> int:
    args = argv[1:]
    serial = option(args, "--serial")
    activation = option(args, "--activation")
    expectations = option(args, "--expect", many=True)
    required = option(args, "--cavities", "")
    required = [c for c in required.split(",") if c]
    closed = "--closed" in args
    if closed:
        args.remove("--closed")
    failures = []
    with h5py.File(args[0], "r") as f:
        ts, events, summary = table(f, "timeseries"), table(f, "events"), table(f, "summary")
        coupling_limit = 5 * cavity_volume_tolerance(f)
    n = min(len(v) for v in ts.values())
    ts = {k: v[:n] for k, v in ts.items()}
    print(f"{len(events.get('time', []))} valve events, {len(summary.get('beat', []))} beat(s), "
          f"{n} rows")
    if len(events.get("time", [])) < 4:
        failures.append("fewer than one full cycle of valve events")

    for c in cavities(ts):
        # Phase order: 0 -> 1 -> 2 -> 3 -> 0 along the rows.
        phase = ts[f"{c}_phase"].astype(int)
        changes = np.flatnonzero(np.diff(phase)) + 1
        for i in changes:
            if (phase[i - 1] + 1) % 4 != phase[i]:
                failures.append(f"{c}: phase {phase[i - 1]} -> {phase[i]} at t = "
                                f"{ts['time'][i]:.2f} ms")
        # The coupling: the deformed mesh holds the 0D volume state.
        v3, v0 = ts[f"{c}_mechanics_volume_mL"], ts[f"{c}_volume_mL"]
        coupling = np.max(np.abs(v3 - v0) / v0)
        # Isovolumetric phases: the closed valves leak (diodes, R_max) by far less than
        # 1e-4 of the volume.
        worst_iso = 0.0
        segments = np.split(np.arange(n), changes)
        for seg in segments:
            # A row's phase is the one after its step (a step that ends at a valve event
            # has the new phase): a segment starts at the event that began its phase.
            if phase[seg[0]] in (1, 3) and len(seg) > 1:
                v = v0[seg]
                worst_iso = max(worst_iso, np.max(np.abs(v - v[0])) / v[0])
        print(f"{c}: coupling |V_3D - V_0D|/V {coupling:.2e} (limit {coupling_limit:.0e}); "
              f"isovolumetric volume change {worst_iso:.2e} (limit 1e-5)")
        if not coupling <= coupling_limit:
            failures.append(f"{c}: the mesh volume differs from the 0D volume by {coupling:.3e}")
        if not worst_iso <= 1e-5:
            failures.append(f"{c}: isovolumetric volume change {worst_iso:.3e} > 1e-5")

    for c in required:
        if c not in cavities(ts):
            failures.append(f"{c} is not a 3D cavity of this run")
            continue
        visited = sorted(set(ts[f"{c}_phase"].astype(int)))
        edv, esv = summary.get(f"{c}_EDV_mL"), summary.get(f"{c}_ESV_mL")
        peak, edp = summary.get(f"{c}_peak_pressure_mmHg"), summary.get(f"{c}_EDP_mmHg")
        print(f"{c}: phases {visited}; EDV {edv}, ESV {esv} mL; EDP {edp}, peak {peak} mmHg")
        if visited != [0, 1, 2, 3]:
            failures.append(f"{c}: phases visited {visited}, not all four")
        if edv is None or esv is None or not np.all(edv - esv > 0.05 * edv):
            failures.append(f"{c}: no PV loop (EDV {edv}, ESV {esv} mL)")
        if peak is None or edp is None or not np.all(peak - edp > 5):
            failures.append(f"{c}: no pressure rise (EDP {edp}, peak {peak} mmHg)")

    if closed:
        blood = ts["total_blood_volume_mL"]
        drift = np.max(np.abs(blood - blood[0])) / blood[0]
        print(f"total blood volume {blood[0]:.4f} mL, largest relative change {drift:.2e} "
              "(limit 1e-8)")
        if not drift <= 1e-8:
            failures.append(f"the blood volume changed by {drift:.3e} of itself")

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
        for c in cavities(ts):
            for key in ("EDV_mL", "ESV_mL", "peak_pressure_mmHg", "stroke_work_mmHg_mL"):
                a, b = sum1.get(f"{c}_{key}"), summary.get(f"{c}_{key}")
                if a is None or b is None or len(a) != len(b):
                    failures.append(f"summary {c}_{key} missing or of different length")
                    continue
                rel = np.nanmax(np.abs(a - b) / np.maximum(np.abs(a), 1e-300))
                print(f"summary {c}_{key} vs serial: {rel:.2e}")
                if not rel <= 1e-4:
                    failures.append(f"summary {c}_{key} differs from the serial run by {rel:.2e}")

    # Regression values of the last beat: NAME=VALUE:TOL (absolute).
    for spec in expectations:
        name, rest = spec.split("=")
        value, tol = (float(x) for x in rest.split(":"))
        got = summary.get(name)
        if got is None:
            failures.append(f"summary column {name} missing")
            continue
        print(f"{name} = {got[-1]:.4f} (expected {value} +- {tol})")
        if not abs(got[-1] - value) <= tol:
            failures.append(f"{name} = {got[-1]:.4f}, expected {value} +- {tol}")

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
                times[times == -1.0] = np.nan  # the file's "not activated"
                print(f"activation_time field: {np.isfinite(times).mean():.3f} of the nodes "
                      f"activated, {np.nanmin(times):.2f} to {np.nanmax(times):.2f} ms")
                if not np.all(np.isfinite(times)):
                    failures.append("nodes without activation time at the end of the run")
                elif not np.nanmax(times) <= reference["last_activation_time"][-1] + 1e-6:
                    failures.append("the activation map holds times after the last upstroke "
                                    "of the electrophysiology alone")
    # The mitral valve (valve 0 of the models) closes only after the wave started.
    closing = events["time"][(events["valve"] == 0) & (events["opens"] == 0)]
    first = reference["first_activation_time"][-1]
    if len(closing) and not closing[0] > first:
        failures.append(f"the mitral valve closed at {closing[0]} ms, before the first "
                        f"upstroke at {first} ms")
    return failures


if __name__ == "__main__":
    sys.exit(main(sys.argv))
