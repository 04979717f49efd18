"""The cavities, pressures, volumes and flows of a circulation or heartbeat results file.

Column names written by the C++ code (src/simulation/circulation_run.h and the heartbeat):

- /timeseries: every state and output of the 0D model with a unit suffix
  (``lv_volume_mL``, ``systemic_arterial_pressure_mmHg``, ``aortic_valve_flow_mL_per_s``);
  per ventricle c ``c_phase`` (codes of src/circulation/phase.h); per 3D cavity
  ``c_mechanics_volume_mL``; the heartbeat also writes ``pressure_mmHg``, ``volume_mL`` and
  ``phase``, aliases of its first 3D cavity.
- /summary: per ventricle c ``c_EDV_mL``, ``c_ESV_mL``, ..., ``c_dpdt_max``, the four
  ``c_<phase>_duration``; per pressure ``name_max_mmHg``, ``name_min_mmHg``,
  ``name_mean_mmHg``; run-wide columns.

A cavity is every prefix c with both ``c_pressure_mmHg`` and ``c_volume_mL`` (the atria of
the closed loop too, without a phase). An old-style heartbeat file has only the unprefixed
``pressure_mmHg``, ``volume_mL`` and ``phase``: it is one cavity with the empty name.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

PRESSURE = "_pressure_mmHg"
VOLUME = "_volume_mL"
FLOW = "_mL_per_s"


@dataclass(frozen=True)
class Cavity:
    """The time-series columns of one cavity.

    Attributes:
        name: column prefix ("lv", "rv", "la"; "" for an old-style file).
        pressure, volume: its pressure [mmHg] and volume [mL] columns.
        phase: its phase column, or None (atria have none).
        mechanics_volume: the volume of its 3D mesh [mL], or None.
    """

    name: str
    pressure: str
    volume: str
    phase: str | None = None
    mechanics_volume: str | None = None

    @property
    def label(self) -> str:
        """"LV", "RV", ...; "cavity" for an old-style file."""
        return self.name.upper() if self.name else "cavity"

    @property
    def right_heart(self) -> bool:
        """True for the right ventricle and atrium (rv, ra)."""
        return self.name in RIGHT_HEART_CAVITIES


#: Cavity names drawn with the right heart (pulmonary side).
RIGHT_HEART_CAVITIES = ("rv", "ra")

#: Vessel pressures of the traces, in drawing order: column, legend, right heart (True) or
#: left heart. Columns a file lacks are skipped. ``aortic_pressure_mmHg`` is the aortic root
#: of old-style files; ``arterial_pressure_mmHg`` and ``atrial_pressure_mmHg`` are the
#: Windkessel's distal and (constant) atrial pressures.
VESSEL_PRESSURES = (
    ("systemic_arterial_pressure_mmHg", "systemic arteries", False),
    ("aortic_root_pressure_mmHg", "aortic root", False),
    ("aortic_pressure_mmHg", "aortic root", False),
    ("arterial_pressure_mmHg", "arteries (Windkessel)", False),
    ("atrial_pressure_mmHg", "atrium (Windkessel)", False),
    ("pulmonary_venous_pressure_mmHg", "pulmonary veins", False),
    ("pulmonary_arterial_pressure_mmHg", "pulmonary arteries", True),
    ("systemic_venous_pressure_mmHg", "systemic veins", True),
)

#: Columns of old-style files and their legends, for the flow panel.
OLD_STYLE_FLOWS = (("flow", "outflow - inflow"), ("aortic_outflow", "aortic outflow"),
                   ("mitral_inflow", "mitral inflow"))


def find_cavities(columns: Iterable[str]) -> list[Cavity]:
    """The cavities of a time series: ventricles (with a phase) first, each group in file
    order; the old-style single cavity when no prefixed one exists; [] if neither."""
    columns = list(columns)
    present = set(columns)
    found = []
    for column in columns:
        if not column.endswith(VOLUME):
            continue
        name = column[: -len(VOLUME)]
        if not name or name.endswith("_mechanics") or name + PRESSURE not in present:
            continue
        found.append(Cavity(name, name + PRESSURE, column,
                            _present(present, name + "_phase"),
                            _present(present, name + "_mechanics" + VOLUME)))
    if not found and {"pressure_mmHg", "volume_mL"} <= present:
        found.append(Cavity("", "pressure_mmHg", "volume_mL", _present(present, "phase"),
                            _present(present, "mechanics_volume_mL")))
    return sorted(found, key=lambda cavity: cavity.phase is None)


def _present(columns: set[str], name: str) -> str | None:
    return name if name in columns else None


def alias_columns(cavities: list[Cavity]) -> set[str]:
    """The heartbeat's unprefixed aliases of its first 3D cavity, when prefixed cavities
    exist (they repeat a cavity's columns)."""
    if not cavities or not cavities[0].name:
        return set()
    return {"pressure_mmHg", "volume_mL", "phase", "mechanics_volume_mL"}


def pressure_traces(columns: Iterable[str], cavities: list[Cavity]
                    ) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """The (column, legend) pairs of the left-heart and of the right-heart pressure panel:
    the cavity pressures, then the vessel pressures that exist."""
    present = set(columns)
    left, right = [], []
    for cavity in cavities:
        (right if cavity.right_heart else left).append((cavity.pressure, cavity.label))
    for column, legend, is_right in VESSEL_PRESSURES:
        if column in present:
            (right if is_right else left).append((column, legend))
    return left, right


def flow_traces(columns: Iterable[str]) -> list[tuple[str, str]]:
    """The valve flows (``mitral_valve_flow_mL_per_s`` -> "mitral"), or the flows of an
    old-style file."""
    columns = list(columns)
    valves = [(c, c[: -len("_valve_flow" + FLOW)].replace("_", " "))
              for c in columns if c.endswith("_valve_flow" + FLOW)]
    if valves:
        return valves
    return [(c, legend) for c, legend in OLD_STYLE_FLOWS if c in columns]


def ventricles(summary: Iterable[str]) -> list[str]:
    """The prefixes c of the /summary columns c_EDV_mL, in file order ([""] for an
    old-style summary with EDV_mL, [] without either)."""
    summary = list(summary)
    names = [c[: -len("_EDV_mL")] for c in summary if c.endswith("_EDV_mL")]
    if not names and "EDV_mL" in summary:
        names = [""]
    return names


#: The per-ventricle /summary columns, without the "c_" prefix, with a short heading and
#: their unit, in table order (src/circulation/model_summary.h).
VENTRICLE_SUMMARY = (
    ("EDV_mL", "EDV", "mL"), ("ESV_mL", "ESV", "mL"), ("SV_mL", "SV", "mL"), ("EF", "EF", "%"),
    ("EDP_mmHg", "EDP", "mmHg"), ("peak_pressure_mmHg", "peak", "mmHg"),
    ("stroke_work_mmHg_mL", "stroke work", "mmHg mL"), ("dpdt_max", "dp/dt max", "mmHg/s"),
    ("dpdt_min", "dp/dt min", "mmHg/s"), ("filling_duration", "filling", "ms"),
    ("isovolumetric_contraction_duration", "IVC", "ms"),
    ("ejection_duration", "ejection", "ms"),
    ("isovolumetric_relaxation_duration", "IVR", "ms"),
)

#: Suffixes of the statistics of one pressure in /summary.
PRESSURE_STATISTICS = ("max", "min", "mean")


@dataclass(frozen=True)
class SummaryGroups:
    """The /summary columns sorted for printing.

    Attributes:
        ventricles: per ventricle prefix c ("" for an old-style file): (column, heading,
            unit) of its columns, the known ones (VENTRICLE_SUMMARY) first; unit None
            where the file's unit is to be used.
        pressures: the names p with p_max_mmHg, p_min_mmHg and p_mean_mmHg, in file order.
        others: the remaining columns but ``beat``, in file order.
    """

    ventricles: dict[str, list[tuple[str, str, str | None]]]
    pressures: list[str]
    others: list[str]


def summary_groups(summary: Iterable[str]) -> SummaryGroups:
    """Sort the /summary column names into ventricles, pressures and the rest."""
    summary = list(summary)
    present = set(summary)
    pressures = []
    for column in summary:
        if column.endswith("_max_mmHg"):
            name = column[: -len("_max_mmHg")]
            if all(f"{name}_{s}_mmHg" in present for s in PRESSURE_STATISTICS):
                pressures.append(name)
    used = {"beat"} | {f"{p}_{s}_mmHg" for p in pressures for s in PRESSURE_STATISTICS}
    groups = {}
    for name in ventricles(summary):
        prefix = f"{name}_" if name else ""
        columns = [(prefix + key, heading, unit) for key, heading, unit in VENTRICLE_SUMMARY
                   if prefix + key in present]
        used |= {column for column, _, _ in columns}
        if prefix:  # further columns of this ventricle, under their own names
            columns += [(c, c[len(prefix):], None) for c in summary
                        if c.startswith(prefix) and c not in used]
            used |= {column for column, _, _ in columns}
        groups[name] = columns
    return SummaryGroups(groups, pressures, [c for c in summary if c not in used])
