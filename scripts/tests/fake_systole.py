"""A fast stand-in for the systole app in the study tests: reads x1, x2 from the .prm,
writes a results file with a /summary row y = x1 + 2 x2 (and z = x1 * x2), quickly.

Usage: python fake_systole.py CASE.prm LAUNCH_LOG

Subsection Fake of the .prm: x1, x2 (the inputs), Sleep (seconds before writing the
results), Fail above (exit 1 with an error line on stderr when x1 exceeds it), Beats (rows
of /summary and valve events). Every launch appends the case folder's name to LAUNCH_LOG.
"""

import sys
import time
from pathlib import Path

from conftest import write_results_file

from systole_post.study import _SET, _SUBSECTION, _END


def read_prm(path):
    values, stack = {}, []
    for line in Path(path).read_text().splitlines():
        if m := _SUBSECTION.match(line):
            stack.append(m.group(1))
        elif _END.match(line) and stack:
            stack.pop()
        elif m := _SET.match(line):
            values[" / ".join(stack + [m.group(2)])] = m.group(4)
    return values


def main():
    prm, log = sys.argv[1], sys.argv[2]
    with open(log, "a") as stream:
        stream.write(Path.cwd().name + "\n")
    values = read_prm(prm)
    x1, x2 = float(values["Fake / x1"]), float(values["Fake / x2"])
    time.sleep(float(values.get("Fake / Sleep", 0)))
    if x1 > float(values.get("Fake / Fail above", "inf")):
        print("Solving step 3 ...")
        print(f"Error: Newton did not converge at x1 = {x1:g}", file=sys.stderr)
        return 1
    beats = int(values.get("Fake / Beats", 1))
    out = Path(values["Output / Directory"]) / values["Output / Run name"]
    out.mkdir(parents=True, exist_ok=True)
    summary = {"beat": list(range(beats)),
               "y": [x1 + 2 * x2 + beat for beat in range(beats)],
               "z_mL": [x1 * x2] * beats}
    events = {"time": [], "beat": [], "valve": [], "opens": [], "lv_pressure_mmHg": []}
    for beat in range(beats):  # valve 1 opens at pressure x1 and closes at x2 + beat
        for opens, pressure in ((1, x1), (0, x2 + beat)):
            for name, value in zip(events, (beat + 0.5 * opens, beat, 1, opens, pressure)):
                events[name].append(value)
    write_results_file(out / "results.h5", {"time": [0.0, 1.0], "step": [0, 1],
                                            "volume": [1.0, x1]}, summary=summary,
                       events=events)
    return 0


if __name__ == "__main__":
    sys.exit(main())
