"""The bench groups: name (the value of `scripts/bench --only`) -> the function that runs the
group and returns its sections of docs/verification.md ({title: markdown}). Every function
takes the parsed arguments (build, quick, full, jobs) and a scratch folder, and prints its
progress and its sections. A full run walks the table in this order, which is the order of
the sections a new docs/verification.md gets."""

from . import (arostica, badinput, biv, cell, checkpoint, circulation, ep, ep_lv, fibres,
               heartbeat, heavy, inverse, land, large, laws, mixed, niederer, p1, p2, p2_mixed,
               p3, postprocess, scaling, tet)

GROUPS = {
    "p1": p1.sections,
    "p2": p2.sections,
    "p2-mixed": p2_mixed.sections,
    "p3": p3.sections,
    "fibres": fibres.sections,
    "heartbeat": heartbeat.sections,
    "biv": biv.sections,
    "badinput": badinput.sections,
    "checkpoint": checkpoint.sections,
    "ep": ep.sections,
    "land": land.sections,
    "niederer": niederer.sections,
    "inverse": inverse.sections,
    "ep-lv": ep_lv.sections,
    "mixed": mixed.sections,
    "scaling": scaling.sections,
    "scaling-th": scaling.th_sections,
    "tet": tet.sections,
    "large": large.sections,
    "arostica": arostica.sections,
    "laws": laws.sections,
    "circulation": circulation.sections,
    "cell": cell.sections,
    "postprocess": postprocess.sections,
    "heavy": heavy.sections,
}
