#!/usr/bin/env python3
"""Check the postprocessors' output of a heartbeat (Postprocess / List of postprocessors).

    check_postprocess.py RESULTS.h5 [--serial SERIAL.h5] [--activation] [--from-timeseries]

- /timeseries has long_axis_shortening, wall_thickening, torsion and ejection_fraction,
  zero at the first step (the reference state), finite everywhere;
- the largest ejection_fraction of each beat (from the deformed mesh's volume) equals the
  beat's lv_EF of /summary (from the 0D volume state) to 0.01 percentage points;
- /summary has aha_NN_peak_strain_{circumferential,longitudinal,radial} and
  aha_NN_activation_time for NN = 01 ... 17, the strains finite and below 1 in magnitude;
  with --activation every segment's activation time is finite and inside the beat;
- with "clinical kinematics" (if its columns are there): its /timeseries columns are finite
  and zero at the first step and at each beat's end-diastolic step (the step at
  end_diastolic_time, the reference of the beat), the volume there is the beat's lv_EDV to
  1e-4 (end-diastole is the largest volume before ejection), the /summary peaks and
  aha_NN_peak_ed_strain_* are finite (strains below 1 in magnitude);
- with --serial, every postprocessor column agrees with the serial run to 1e-6 (relative
  to the column's scale): 2 ranks reproduce 1 rank;
- with --from-timeseries, the EF and the end-diastolic volume are checked against the
  /timeseries volumes instead of /summary's lv_EF and lv_EDV (the largest ejection_fraction
  is max (V_max(t) - V(t)) / V_max(t), V_max(t) the largest volume so far in the beat; the
  end-diastolic volume the largest before the beat's first ejection step): for a first beat
  from the unloaded state, whose mitral valve closes twice (after the first filling and
  again at the end of the beat, which /summary takes).
"""

import sys

import h5py
import numpy as np

TIMESERIES = ["long_axis_shortening", "wall_thickening", "torsion", "ejection_fraction"]
COMPONENTS = ["circumferential", "longitudinal", "radial"]
CLINICAL = [f"{layer}_{c}_strain" for layer in ("global", "endocardial")
            for c in ("longitudinal", "circumferential", "radial")] + [
    "twist", "torsion_per_length", "av_plane_displacement", "apex_displacement",
    "wall_thickening_ed"]


def clinical_summary_columns():
    return ([f"peak_{name}" for name in CLINICAL] + ["end_diastolic_time"] +
            [f"aha_{n:02d}_peak_ed_strain_{c}" for n in range(1, 18) for c in COMPONENTS])


def lv_volume(ts):
    """The LV (first cavity) volume [mL] of every step."""
    return ts["lv_volume_mL"] if "lv_volume_mL" in ts else ts["volume_mL"]


def timeseries_edv(ts, summary):
    """Per beat: the largest LV volume before the beat's first ejection step."""
    edv = []
    for b in range(len(summary["start_time"])):
        in_beat = np.flatnonzero(ts["beat"] == b)
        ejecting = in_beat[ts["phase"][in_beat] == 2]
        before = in_beat[in_beat < ejecting[0]] if ejecting.size else in_beat
        edv.append(lv_volume(ts)[before].max())
    return np.array(edv)


def check_clinical(ts, summary, from_timeseries=False):
    """The "clinical kinematics" columns (the errors found)."""
    errors = []
    for name in CLINICAL:
        if name not in ts:
            return [f"/timeseries/{name} missing"]
        if not np.all(np.isfinite(ts[name])):
            errors.append(f"/timeseries/{name} is not finite")
        if abs(ts[name][0]) > 1e-12:
            errors.append(f"/timeseries/{name} is {ts[name][0]} at the first step")
    for name in clinical_summary_columns():
        if name not in summary:
            errors.append(f"/summary/{name} missing")
        elif not np.all(np.isfinite(summary[name])):
            errors.append(f"/summary/{name} = {summary[name]} is not finite")
        elif "strain" in name and not np.all(np.abs(summary[name]) < 1):
            errors.append(f"/summary/{name} = {summary[name]}: not a strain")
    if errors:
        return errors
    edvs = timeseries_edv(ts, summary) if from_timeseries else summary["lv_EDV_mL"]
    for b, (start, ed, edv) in enumerate(zip(summary["start_time"],
                                             summary["end_diastolic_time"], edvs)):
        at = np.flatnonzero((ts["beat"] == b) & (np.abs(ts["time"] - start - ed) < 1e-9))
        if at.size != 1:
            errors.append(f"beat {b}: no step at end_diastolic_time {ed} ms")
            continue
        i = at[0]
        for name in CLINICAL:
            if abs(ts[name][i]) > 1e-12:
                errors.append(f"beat {b}: /timeseries/{name} is {ts[name][i]} at end-diastole")
        volume = lv_volume(ts)[i]
        if not 0 <= edv - volume <= 1e-4 * edv:
            errors.append(f"beat {b}: volume {volume} mL at end-diastole, lv_EDV {edv} mL")
    return errors


def aha_columns():
    names = []
    for n in range(1, 18):
        names += [f"aha_{n:02d}_peak_strain_{c}" for c in COMPONENTS]
        names.append(f"aha_{n:02d}_activation_time")
    return names


def main(argv):
    args = list(argv)
    serial = None
    if "--serial" in args:
        i = args.index("--serial")
        serial = args[i + 1]
        del args[i : i + 2]
    activation = "--activation" in args
    if activation:
        args.remove("--activation")
    from_timeseries = "--from-timeseries" in args
    if from_timeseries:
        args.remove("--from-timeseries")
    errors = []
    with h5py.File(args[0], "r") as f:
        ts = {k: f["timeseries"][k][()] for k in f["timeseries"]}
        summary = {k: f["summary"][k][()] for k in f["summary"]}
    for name in TIMESERIES:
        if name not in ts:
            errors.append(f"/timeseries/{name} missing")
            continue
        if not np.all(np.isfinite(ts[name])):
            errors.append(f"/timeseries/{name} is not finite")
        if abs(ts[name][0]) > 1e-12:
            errors.append(f"/timeseries/{name} is {ts[name][0]} at the first step")
    if not errors:
        for b, ef in enumerate(summary["lv_EF"]):
            in_beat = ts["beat"] == b
            largest = 100 * ts["ejection_fraction"][in_beat].max()  # lv_EF is in %
            if from_timeseries:
                v = lv_volume(ts)[in_beat]
                v_max = np.maximum.accumulate(v)
                ef = 100 * np.max((v_max - v) / v_max)
            if abs(largest - ef) > 0.01:
                errors.append(f"beat {b}: largest ejection_fraction {largest} != lv_EF {ef}")
    for name in aha_columns():
        if name not in summary:
            errors.append(f"/summary/{name} missing")
            continue
        v = summary[name]
        if "strain" in name and not np.all(np.isfinite(v) & (np.abs(v) < 1)):
            errors.append(f"/summary/{name} = {v}: not a finite strain")
        if activation and "activation" in name:
            start, end = summary["start_time"], summary["end_time"]
            if not np.all(np.isfinite(v) & (v >= 0) & (v <= end - start)):
                errors.append(f"/summary/{name} = {v}: not inside the beat")
    clinical = "global_longitudinal_strain" in ts
    if clinical:
        errors += check_clinical(ts, summary, from_timeseries)
    if serial is not None:
        groups = [("timeseries", TIMESERIES), ("summary", aha_columns())]
        if clinical:
            groups += [("timeseries", CLINICAL), ("summary", clinical_summary_columns())]
        with h5py.File(serial, "r") as g:
            for group, names in groups:
                for name in names:
                    a, b = f_read(args[0], group, name), g[group][name][()]
                    scale = max(np.nanmax(np.abs(b)), 1e-12) if b.size else 1
                    if a.shape != b.shape or not np.allclose(
                        a, b, rtol=0, atol=1e-6 * scale, equal_nan=True
                    ):
                        errors.append(f"/{group}/{name} differs from the serial run")
    for e in errors:
        print("FAIL:", e)
    if not errors:
        print(f"postprocessors ok: {len(ts['time'])} steps, {len(summary['lv_EF'])} beat(s)"
              + (", with clinical kinematics" if clinical else ""))
    return 1 if errors else 0


def f_read(path, group, name):
    with h5py.File(path, "r") as f:
        return f[group][name][()]


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
