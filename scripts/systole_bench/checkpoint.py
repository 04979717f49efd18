"""The group 'checkpoint': one beat of the default heartbeat with checkpoints."""

from __future__ import annotations

from pathlib import Path

from .heartbeat import run_default_heartbeat


def run_checkpoint(ranks: int, build: Path, workdir: Path, interval: int = 10) -> dict:
    """One beat of the default heartbeat with a checkpoint every `interval` steps: the write
    time per checkpoint and the size of the last checkpoint by part (from /statistics)."""
    row, results = run_default_heartbeat(
        f"checkpoint_{ranks}", ranks, build, workdir,
        extra="\nsubsection Circulation\n  set Number of beats = 1\nend\n",
        output=f"  set Checkpoint interval = {interval}\n")
    if results is None:
        return row
    st = results.statistics
    row["n"] = int(st["checkpoints"])
    row["seconds"] = st["checkpoint_seconds"] / max(1, row["n"])
    row["dofs"] = int(st["mechanics_dofs"])
    row["wall"] = st["wall_time"]
    row["ep_nodes"] = int(st["ep_nodes"])
    folder = workdir / results.statistics_text["last_checkpoint"]
    sizes = {"mechanics": 0, "ep": 0, "state": 0}
    for f in folder.iterdir():
        part = "mechanics" if f.name.startswith("mechanics") else \
            "ep" if f.name.startswith("ep.") else "state"
        sizes[part] += f.stat().st_size
    row["sizes"] = sizes
    return row


def checkpoint_section(rows: list[dict]) -> str:
    """Checkpoint size per DOF and write time of the default heartbeat."""
    lines = ["## Checkpoints of the default heartbeat (parameters/lv_heartbeat.prm)",
             "One beat with `Output / Checkpoint interval = 10`. A checkpoint holds the mechanics "
             "mesh with its attached data (three displacement vectors: the last two accepted "
             "states and the iterate of the held factorization; the tension of that iterate and "
             "the activation records per quadrature point), the EP mesh with the potential, the "
             "ionic states and the activation times per node, and the small state (`state.bin`: "
             "BDF history, beat recorder, counters), plus the parameters and the manifest. The "
             "write time includes the CRC-32 manifest and fsync, not the refactorization a "
             "resume needs.", "",
             "| ranks | mechanics DOFs | EP nodes | checkpoints | write time [s] | mechanics part "
             "[bytes per DOF] | EP part [bytes per node] | state.bin etc. [kB] | total [kB] | run "
             "wall time [s] |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['ranks']} | failed: {r.get('error', '')} |||||||||")
            continue
        s = r["sizes"]
        lines.append(f"| {r['ranks']} | {r['dofs']} | {r['ep_nodes']} | {r['n']} | "
                     f"{r['seconds']:.3f} | {s['mechanics'] / r['dofs']:.0f} | "
                     f"{s['ep'] / r['ep_nodes']:.0f} | {s['state'] / 1024:.1f} | "
                     f"{sum(s.values()) / 1024:.0f} | {r['wall']:.1f} |")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Checkpoints of the default heartbeat (parameters/lv_heartbeat.prm)"
    print("running one beat of the default heartbeat with checkpoints ...", flush=True)
    text = checkpoint_section([run_checkpoint(2, args.build, workdir)])
    print(text, flush=True)
    return {title: text}
