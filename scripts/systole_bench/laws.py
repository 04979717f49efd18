"""The group 'laws': Land problem 2 with the isotropic laws at the same shear modulus."""

from __future__ import annotations

from pathlib import Path

from .core import BUSY_NOTE, LAND2_PENALTY, Case, run


#: The isotropic laws of the "laws" group, at the small-strain shear modulus of the isotropic
#: Guccione law of Land problem 2 (C/2 = 5 kPa): (law, entries of its subsection, the shear
#: modulus in its parameters). The unit test "Each isotropic law has the small-strain shear
#: modulus its documentation states" checks these sets.
LAWS_SHEAR_MODULUS = 5.0
ISOTROPIC_LAWS = [
    ("Guccione", {"C": "10", "b_f": "1", "b_t": "1", "b_fs": "1"}, "C/2"),
    ("neo-Hookean", {"mu": "5"}, "mu"),
    ("Mooney-Rivlin", {"c1": "2", "c2": "0.5"}, "2 (c1 + c2)"),
    ("Fung isotropic", {"mu": "10", "gamma": "0.5"}, "mu gamma"),
    ("Veronda-Westman", {"c1": "10", "gamma": "0.5"}, "c1 gamma"),
]
#: The small pressures [kPa] of the "laws" group's second table.
LAWS_SMALL_PRESSURES = ["0.01", "0.1"]
#: Formulations of the "laws" group: the penalty file, and the incompressible mixed
#: formulation in 10 equal load steps (as in the mixed group).
LAWS_FORMULATIONS = [
    ("penalty, kappa = 1000 kPa", {"Material/Incompressibility": "penalty"}),
    ("incompressible, Q2-P1disc", {"Material/Incompressibility": "incompressible",
                                   "Load steps": "10",
                                   "Mechanics/Adaptive load steps": "false"}),
]


def laws_table(build: Path, workdir: Path) -> tuple[list[str], str]:
    """The table at 10 kPa (its lines) and the undeformed cavity volume it found."""
    lines = ["| law | parameters [kPa, -] | formulation | DOFs | pressure reached [kPa] "
             "| endo apex z [mm] | endo apex displacement [mm] | epi apex z [mm] "
             "| cavity volume [mm³] | volume change [%] | load steps (cuts) "
             "| Newton iterations | wall [s] |"]
    lines.append("|" + "---|" * (lines[0].count("|") - 1))
    busy = False
    undeformed = []
    stopped = []
    for law, entries, modulus in ISOTROPIC_LAWS:
        changes = {"Passive law": law}
        changes.update({f"Material/{law}/{k}": v for k, v in entries.items()})
        text = ", ".join(f"{k} = {v}" for k, v in entries.items()) + \
            f" ({modulus} = {LAWS_SHEAR_MODULUS:g})"
        for formulation, extra in LAWS_FORMULATIONS:
            case = Case("laws", "land_problem2.prm", f"{law}, {formulation}",
                        {**LAND2_PENALTY, **changes, **extra})
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...",
                  flush=True)
            r = run(case, build, workdir)
            state = r if r["ok"] else r.get("last_converged")
            if state is None:
                lines.append(f"| {law} | {text} | {formulation} | failed: {r['error']} |")
                continue
            v = state["values"]
            v0, v1 = state["volume"]
            undeformed.append(v0)
            cells = (f"| {state['pressure']:.3g} | {v['endo_apex_z']:.3f} "
                     f"| {v['endo_apex_z'] + 17.0:.3f} | {v['epi_apex_z']:.3f} | {v1:.1f} "
                     f"| {100.0 * (v1 / v0 - 1.0):.1f} |")
            if r["ok"]:
                assert abs(r["pressure"] - 10.0) < 1e-9, "the run did not reach 10 kPa"
                busy = busy or r["busy"]
                mark = " *" if r["busy"] else ""
                lines.append(f"| {law} | {text} | {formulation} | {r['dofs']} {cells} "
                             f"{r['steps']} ({r['cut']}) | {r['newton']} "
                             f"| {r['wall']:.1f}{mark} |")
            else:
                stopped.append(f"{law} ({formulation})")
                lines.append(f"| {law} | {text} | {formulation} | {cells} stopped † | | |")
    if busy:
        lines.append(BUSY_NOTE)
    if stopped:
        lines.append("\n† Stopped short of 10 kPa (the load step could not be cut further): "
                     "without exponential stiffening, at this shear modulus the cavity keeps "
                     "growing under a pressure that hardly rises, or falls (a limit point of the "
                     "pressure-volume curve: the inflation instability of a rubber balloon), so "
                     "pressure-controlled loading finds no equilibrium; the row is the last "
                     "converged state: " + ", ".join(stopped) + ".")
    return lines, f"{undeformed[0]:.1f}" if undeformed else "?"


def laws_small_table(build: Path, workdir: Path) -> list[str]:
    """The table at small pressures (its lines)."""
    # At small pressures every law is close to linear: the same shear modulus must give about
    # the same response (a check of the matched parameters).
    small = ["| law | " + " | ".join(
        f"endo apex displacement at {p} kPa [mm] | epi apex displacement at {p} kPa [mm] "
        f"| volume change at {p} kPa [%]" for p in LAWS_SMALL_PRESSURES) + " |"]
    small.append("|" + "---|" * (small[0].count("|") - 1))
    for law, entries, _ in ISOTROPIC_LAWS:
        cells = []
        for pressure in LAWS_SMALL_PRESSURES:
            changes = {"Passive law": law, "Pressure": pressure}
            changes.update({f"Material/{law}/{k}": v for k, v in entries.items()})
            case = Case("laws", "land_problem2.prm", f"{law}, {pressure} kPa",
                        {**LAND2_PENALTY, **changes})
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...",
                  flush=True)
            r = run(case, build, workdir)
            if not r["ok"]:
                cells.append(f"failed: {r['error']} | |")
                continue
            v = r["values"]
            volume0, volume1 = r["volume"]
            cells.append(f"{v['endo_apex_z'] + 17.0:.3e} | {v['epi_apex_z'] + 20.0:.3e} "
                         f"| {100.0 * (volume1 / volume0 - 1.0):.4f}")
        small.append(f"| {law} | " + " | ".join(cells) + " |")
    return small


def laws_section(build: Path, workdir: Path) -> str:
    """Land problem 2 with each isotropic law at the same small-strain shear modulus: apex
    positions and cavity volume at 10 kPa, penalty and incompressible mixed. A run that stops
    short of 10 kPa (a limit point of the pressure-volume curve: no equilibrium under a
    larger pressure) is reported at its last converged pressure."""
    lines, v0 = laws_table(build, workdir)
    small = laws_small_table(build, workdir)
    return (
        "## Land problem 2 with the isotropic laws at the same shear modulus\n"
        "`parameters/land_problem2.prm` as shipped until 2026-12-07 (the penalty formulation on "
        "the 16 x 5 ventricle, Q2, direct solver, 10 kPa endocardial pressure, 2 ranks) with its law replaced by each isotropic law at the "
        f"small-strain shear modulus mu0 = {LAWS_SHEAR_MODULUS:g} kPa of the shipped isotropic "
        "Guccione law (C/2, C = 10 kPa); the formula in parentheses is mu0 in the law's "
        "parameters. Fung isotropic and Veronda-Westman use gamma = 1/2, the exponent that "
        "matches the Guccione exponent E:E to leading order (Ibar1 - 3 = 2 E:E + O(|E|^3) for an "
        "isochoric deformation). Formulations: the penalty file (bulk modulus 1000 kPa, "
        "the file's adaptive load steps) and the incompressible mixed formulation in 10 equal "
        "load steps. Endocardial apex displacement: its deformed z less the reference -17 mm; "
        "cavity volume: the endocardium closed by the base plane (undeformed "
        f"{v0} mm³ on this mesh, exact 2492.13 mm³), and its change. Reference for Guccione: "
        "endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... "
        "-28.1).\n\n" + "\n".join(lines) + "\n\n"
        "The same laws (penalty) at small pressures, where the matched shear modulus should "
        "give nearly the same response. The apex displacement is a small difference of wall "
        "thinning and elongation, so it is nonlinear already at these loads, and the laws part "
        "as the pressure grows, in two pairs whose energies agree to second order in the "
        "Green-Lagrange strain E: Veronda-Westman with gamma = 1/2 and the isotropic Guccione "
        "law (c1 (e^{gamma (I1 - 3)} - 1) - c1 gamma/2 (I2 - 3) = c1 gamma E:E + c1 gamma "
        "(2 gamma - 1) (tr E)^2 + O(|E|^3), since I1 - 3 = 2 tr E and I2 - 3 = 4 tr E "
        "+ 2 (tr E)^2 - 2 E:E), and Fung isotropic and neo-Hookean (mu/2 (e^{gamma (I1 - 3)} "
        "- 1) = mu gamma tr E + mu gamma^2 (tr E)^2 + ..., and tr E is itself of second order "
        "near J = 1).\n\n"
        + "\n".join(small) + "\n")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Land problem 2 with the isotropic laws at the same shear modulus"
    text = laws_section(args.build, workdir)
    print(text, flush=True)
    return {title: text}
