#!/usr/bin/env python3
"""A coarse, structured all-hexahedral mesh of the idealized biventricular (BiV) heart.

The shape is the one of scripts/make_biv_mesh.py (the cardiac-geometries `biv_ellipsoid`:
LV cavity and wall ellipsoids, RV cavity and wall ellipsoids, base plane z = 25 mm), the
boundary parts the same (lv_endocardium 1, rv_endocardium 2, epicardium 3, base 4), but the
cells are a block structure built here, not gmsh's split tetrahedra:

* The LV wall is a thick shell: a quadrilateral mesh of its epicardium extruded through
  `--lv-layers` layers onto the endocardium. The epicardial mesh lives in a polar chart
  q = f (cos theta, sin theta), |q| <= 1, f the polar angle from the apex as a fraction of the
  base angle (the reference of the LV generator, geometry/ellipsoid.cc): a rectangular cap of
  `--cap` x N cells around the apex and a ring of 2 (cap + N) columns and `--rows` rows up to
  the base circle |q| = 1. A point of the chart at transmural fraction t is on the ellipsoid
  of semi-axes LV_ENDO + 5 t mm at the polar angle f * base angle(t), so every level keeps its
  base on the plane z = 25.
* The RV sits on the footprint of the ring columns that start on the cap's side facing the RV
  (RV-local columns -A..A, A = N/2, all rows). Its boundary (columns +-A, row 0) lies on the
  curve where the RV epicardium meets the LV epicardium, the line inside it (columns
  +-(A-1), row 1) on the curve where the RV endocardium meets it (the junctions, found in the
  chart by bisection; arms from the base to `--corner` of their length, the chord round the
  bottom between). Over the footprint two layers of cells: the lower one is the RV cavity
  (not meshed) inside the inner line and the junction wall over the strip between the two
  lines; the upper one is the RV free wall. Free-wall nodes lie on the rays along the LV
  epicardial normal (RV endocardium, RV epicardium); the junction wall rises one cell up the
  RV endocardium from the inner junction, and its outer nodes lie where rays from there
  cross the RV epicardium.
* The chart's free nodes are placed by Laplace smoothing with the junction nodes fixed at
  equal arc length along their pieces, so the grid lines bend to follow the junctions.
* Then a pattern search moves nodes to raise the smallest scaled Jacobian (improve(): within
  each node's surfaces or curve; the cavity walls only in cells below `--free-below`).
* Resolution: the RV free wall over its cavity has N - 2 columns and rows - 1 rows; its flat
  facets cut the cavity where the free wall turns round towards the junctions (the RV volume
  error lies within 1.5 mm of the RV endocardium, most of it in the anterior and posterior
  thirds). The cap's cells across the chord (`--cap`) touch neither the RV nor its junctions,
  so the defaults spend the cells on N: cap 0.3 N, rows 0.8 N (N = 10: 580 cells, the RV
  8.4 % below the smooth shape; the former cap 0.8 N and rows N left 12.1 % with 630 cells
  at N = 8).

Every boundary node lies on its exact surface (ellipsoid or base plane; junction nodes on
both), so the cavity volumes converge to the smooth shape's under refinement (--cells).
numpy only; writes ASCII gmsh 2.2 (hexahedra, boundary quadrangles with their physical
surfaces), read by Systole's `Geometry / Type = gmsh`; prints the scaled Jacobians.

  python3 scripts/make_biv_hex_mesh.py -o meshes/biv_hex_coarse.msh
  python3 scripts/make_biv_hex_mesh.py --cells 12 -o meshes/biv_hex_fine.msh
"""

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from systole_post.biv_geometry import BASE_Z, LV_ENDO, LV_WALL, RV_ENDO, RV_WALL, grown

RV_EPI = grown(RV_ENDO, RV_WALL)
LV_EPI = grown(LV_ENDO, LV_WALL)


def set_shape(base_z, lv_wall):
    """Another cut and LV wall of the shape (--base-z, --lv-wall): rebinds this module's base
    plane, LV wall thickness and LV epicardium, which every function here reads."""
    global BASE_Z, LV_WALL, LV_EPI
    BASE_Z, LV_WALL = base_z, lv_wall
    LV_EPI = grown(LV_ENDO, LV_WALL)
    SURFACES["lv_epi"] = LV_EPI


def level(ellipsoid, x):
    c, r = np.asarray(ellipsoid[0]), np.asarray(ellipsoid[1])
    return np.sum(((x - c) / r) ** 2, axis=-1) - 1.0


def normal(ellipsoid, x):
    c, r = np.asarray(ellipsoid[0]), np.asarray(ellipsoid[1])
    g = 2 * (x - c) / r**2
    return g / np.linalg.norm(g)


def project(ellipsoid, x, on_base=False):
    """Radial projection onto the ellipsoid from its centre (within the base plane if asked)."""
    c, r = np.asarray(ellipsoid[0], dtype=float), np.asarray(ellipsoid[1], dtype=float)
    if on_base:
        centre = np.array([c[0], c[1], BASE_Z])
        s = 1 - ((BASE_Z - c[2]) / r[2]) ** 2
        d = x - centre
        d[2] = 0
        scale = math.sqrt(s / np.sum((d[:2] / r[:2]) ** 2))
        return centre + scale * d
    d = x - c
    return c + d / math.sqrt(np.sum((d / r) ** 2))


def ray_hit(ellipsoid, x, direction):
    """The first positive s with x + s direction on the ellipsoid."""
    c, r = np.asarray(ellipsoid[0]), np.asarray(ellipsoid[1])
    p, d = (x - c) / r, direction / r
    a, b, cc = d @ d, 2 * p @ d, p @ p - 1
    disc = b * b - 4 * a * cc
    if disc < 0:
        raise RuntimeError(f"ray from {x} misses the ellipsoid {ellipsoid}")
    roots = sorted([(-b - math.sqrt(disc)) / (2 * a), (-b + math.sqrt(disc)) / (2 * a)])
    s = [t for t in roots if t > 1e-9]
    if not s:
        raise RuntimeError(f"ray from {x} has no positive hit on {ellipsoid}")
    return x + s[0] * direction


def lv_point(q, t):
    """The LV wall point of chart position q (|q| <= 1) at transmural fraction t."""
    a, b, c = (np.asarray(LV_ENDO[1]) + LV_WALL * t)
    base_angle = math.acos(-BASE_Z / c)
    f = math.hypot(q[0], q[1])
    nu = f * base_angle
    s = math.sin(nu) / f if f > 1e-14 else base_angle
    return np.array([a * s * q[0], b * s * q[1], -c * math.cos(nu)])


def junction(ellipsoid, centre=(0.55, 0.0), n=2000):
    """The curve in the chart where the LV epicardium meets @p ellipsoid: a polyline from the
    base circle (theta > 0, anterior) round the bottom to the base circle (theta < 0), found by
    bisection along rays from a chart point inside it."""
    centre = np.asarray(centre)
    points = []
    for phi in np.linspace(-math.pi, math.pi, n, endpoint=False):
        d = np.array([math.cos(phi), math.sin(phi)])
        # The largest r with centre + r d inside the chart disk.
        bd = centre @ d
        r_max = -bd + math.sqrt(bd * bd - centre @ centre + 1)
        g = lambda r: level(ellipsoid, lv_point(centre + r * d, 1.0))  # noqa: E731
        if g(r_max) < 0:
            points.append(None)  # the ray reaches the base inside the RV: no junction here
            continue
        lo, hi = 0.0, r_max
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if g(mid) < 0 else (lo, mid)
        points.append(centre + 0.5 * (lo + hi) * d)
    # The rays that reach the base form one run of None: rotate so the curve starts after it.
    k = max(i for i in range(n) if points[i] is None and points[(i + 1) % n] is not None)
    ordered = [points[(k + 1 + i) % n] for i in range(n)]
    ordered = [p for p in ordered if p is not None]
    # End points on the base circle: bisection along the circle between the last ray point
    # and the base.
    curve = np.array(ordered)
    if curve[0][1] < 0:
        curve = curve[::-1]  # start anterior (theta > 0)
    ends = []
    for p in (curve[0], curve[-1]):
        theta0 = math.atan2(p[1], p[0])
        g = lambda th: level(ellipsoid, lv_point(np.array([math.cos(th), math.sin(th)]), 1.0))  # noqa: E731
        lo, hi = 0.0, theta0  # g(0) < 0 (inside the RV at theta = 0), g(theta0) > 0 assumed
        if g(hi) < 0:
            hi = theta0 + math.copysign(0.5, theta0)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if g(mid) < 0 else (lo, mid)
        ends.append(np.array([math.cos(0.5 * (lo + hi)), math.sin(0.5 * (lo + hi))]))
    return np.vstack([ends[0], curve, ends[1]])


def resample(curve, n_edges):
    """n_edges + 1 points at equal arc length (measured on the LV epicardium) along a chart
    polyline."""
    x = np.array([lv_point(q, 1.0) for q in curve])
    s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(x, axis=0), axis=1))])
    targets = np.linspace(0, s[-1], n_edges + 1)
    return np.array([[np.interp(t, s, curve[:, d]) for d in range(2)] for t in targets])


class Mesh:
    def __init__(self):
        self.nodes = []
        self.index = {}

    def node(self, key, x):
        if key not in self.index:
            self.index[key] = len(self.nodes)
            self.nodes.append(np.asarray(x, dtype=float))
        return self.index[key]


def corner_split(curve, fraction):
    """Indices of the two points of a junction polyline (chart) at @p fraction and
    1 - fraction of its length on the LV epicardium: where the arms (from the base) end and
    the chord (round the bottom) begins."""
    x = np.array([lv_point(q, 1.0) for q in curve])
    s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(x, axis=0), axis=1))])
    s /= s[-1]
    return int(np.argmin(np.abs(s - fraction))), int(np.argmin(np.abs(s - 1 + fraction)))


def resample_u(curve, n_arm, n_chord, fraction):
    """Points along a junction: n_arm edges from the anterior base end to the anterior corner,
    n_chord edges round the bottom to the posterior corner, n_arm edges to the posterior base
    end; equal arc length within each piece."""
    a, b = corner_split(curve, fraction)
    return np.vstack([resample(curve[: a + 1], n_arm), resample(curve[a : b + 1], n_chord)[1:],
                      resample(curve[b:], n_arm)[1:]])


def build(N, rows, lv_layers, fraction=0.35, Nx=0):
    """N: cells along the junction's chord (even); rows: ring rows from the cap to the base;
    Nx: cells of the cap across the chord (default 0.3 N)."""
    Ny = N
    Nx = Nx or max(2, round(0.3 * N))
    A = Ny // 2
    # --- the chart: a rectangular cap (Nx x Ny cells, its +x side on the junction's chord)
    # and a ring of 2 (Nx + Ny) columns and `rows` rows up to the base circle.
    perimeter = ([(Nx, b) for b in range(0, Ny)] + [(a, Ny) for a in range(Nx, 0, -1)]
                 + [(0, b) for b in range(Ny, 0, -1)] + [(a, 0) for a in range(0, Nx)])
    n_theta = len(perimeter)
    # Column c of the ring starts at perimeter node c; footprint columns are 0..Ny, and the
    # RV-local index i = c - A runs over -A..A.
    position = {}
    for a in range(Nx + 1):
        for b in range(Ny + 1):
            position[("cap", a, b)] = np.array([-0.6 + 0.85 * a / Nx, -0.6 + 1.2 * b / Ny])
    cap_key = {ab: ("ring", c, 0) for c, ab in enumerate(perimeter)}

    def key_of(kind, a, b):
        if kind == "cap":
            return cap_key.get((a, b), ("cap", a, b))
        return ("ring", a % n_theta, b)

    for c, ab in enumerate(perimeter):
        p0 = position[("cap",) + ab]
        theta = math.atan2(p0[1], p0[0])
        for j in range(rows + 1):
            f = np.linalg.norm(p0) + (1 - np.linalg.norm(p0)) * j / rows
            position[("ring", c, j)] = f * np.array([math.cos(theta), math.sin(theta)])
    for ab in list(position):
        if ab[0] == "cap" and (ab[1], ab[2]) in cap_key:
            del position[ab]
    quads = ([tuple(key_of("cap", *ab) for ab in ((a, b), (a + 1, b), (a + 1, b + 1), (a, b + 1)))
              for a in range(Nx) for b in range(Ny)]
             + [tuple(key_of("ring", *cj) for cj in ((c, j), (c + 1, j), (c + 1, j + 1), (c, j + 1)))
                for c in range(n_theta) for j in range(rows)])

    # Junction curves: outer (RV epicardium) on columns +-A and row 0, inner (RV
    # endocardium) on columns +-(A-1) and row 1 (i = c - A).
    def u_keys(a, jb):
        return ([(a, j) for j in range(rows, jb, -1)] + [(i, jb) for i in range(a, -a, -1)]
                + [(-a, j) for j in range(jb, rows + 1)])

    pinned = set()
    for ellipsoid, a, jb in ((RV_EPI, A, 0), (RV_ENDO, A - 1, 1)):
        keys = u_keys(a, jb)
        points = resample_u(junction(ellipsoid), rows - jb, 2 * a, fraction)
        for (i, j), p in zip(keys, points):
            key = ("ring", (i + A) % n_theta, j)
            position[key] = p
            pinned.add(key)

    # Laplace smoothing of the free chart nodes (base nodes slide on the circle).
    neighbours = {}
    for q in quads:
        for k in range(4):
            neighbours.setdefault(q[k], set()).update((q[k - 1], q[(k + 1) % 4]))
    free = [k for k in position if k not in pinned]
    for _ in range(500):
        new = {}
        for k in free:
            m = np.mean([position[n] for n in neighbours[k]], axis=0)
            if k[0] == "ring" and k[2] == rows:
                m /= np.linalg.norm(m)
            new[k] = m
        position.update(new)

    # --- LV nodes ---------------------------------------------------------------------------
    mesh = Mesh()

    def lv_node(key, k):
        return mesh.node((key, k), lv_point(position[key], k / lv_layers))

    cells = []
    for quad in quads:
        for k in range(lv_layers):
            cells.append([lv_node(key, k) for key in quad] + [lv_node(key, k + 1) for key in quad])

    # --- RV nodes over the footprint ----------------------------------------------------------
    j0 = 0

    def cls(i, j):
        if abs(i) == A or j == j0:
            return "outer"
        if abs(i) == A - 1 or j == j0 + 1:
            return "inner"
        return "inside"

    d_rise = RV_WALL * 6 / N  # the junction wall's height [mm], one cell

    def lv_frame(i, j):
        E = lv_point(position[("ring", (i + A) % n_theta, j)], 1.0)
        n = normal(LV_EPI, E)
        if j == rows:  # base: stay in the plane z = BASE_Z
            n[2] = 0
            n /= np.linalg.norm(n)
        return E, n

    def flat(v, base):
        if base:
            v = v.copy()
            v[2] = 0
        return v / np.linalg.norm(v)

    rv_pos = {}
    for i in range(-A, A + 1):
        for j in range(j0, rows + 1):
            base = j == rows
            E, n = lv_frame(i, j)
            c = cls(i, j)
            if c == "inside":
                rv_pos[(i, j)] = (ray_hit(RV_ENDO, E, n), ray_hit(RV_EPI, E, n))
            elif c == "inner":
                # Up the RV endocardium from the junction (its steepest direction away from
                # the LV epicardium), then along the LV normal to the RV epicardium.
                nr = normal(RV_ENDO, E)
                p1 = project(RV_ENDO, E + d_rise * flat(n - (n @ nr) * nr, base), on_base=base)
                rv_pos[(i, j)] = (p1, ray_hit(RV_EPI, p1, n))
    for i in range(-A, A + 1):
        for j in range(j0, rows + 1):
            if cls(i, j) != "outer":
                continue
            base = j == rows
            # From the RV endocardial node of the inner partner (the junction node across the
            # strip) the RV epicardium across the wall (the strip's direction from the partner's
            # junction to this one's) and, at the bend, along the diagonal between that
            # direction and the LV normal.
            pi = i - (1 if i == A else -1 if i == -A else 0)
            pj = j + (1 if j == j0 else 0)
            p1 = rv_pos[(pi, pj)][0]
            E_in, n = lv_frame(pi, pj)
            E_out, _ = lv_frame(i, j)
            m = flat(E_out - E_in, base)
            rv_pos[(i, j)] = (ray_hit(RV_EPI, p1, m), ray_hit(RV_EPI, p1, flat(m + n, base)))

    def rv_node(i, j, k):
        if k == 0:
            return lv_node(("ring", (i + A) % n_theta, j), lv_layers)
        return mesh.node(("rv", i, j, k), rv_pos[(i, j)][k - 1])

    cavity = []
    for i in range(-A, A):
        for j in range(j0, rows):
            quad = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            strip = i in (-A, A - 1) or j == j0
            for k in range(2):
                cell = [rv_node(a, b, k) for a, b in quad] + [rv_node(a, b, k + 1) for a, b in quad]
                if k == 0 and not strip:
                    cavity.append(cell)
                else:
                    cells.append(cell)
    return np.array(mesh.nodes), np.array(cells), cavity


# For each corner of a hexahedron (gmsh/VTK order), its three edge neighbours, right-handed.
CORNER_NEIGHBOURS = np.array(
    [[1, 3, 4], [2, 0, 5], [3, 1, 6], [0, 2, 7], [7, 5, 0], [4, 6, 1], [5, 7, 2], [6, 4, 3]]
)
SURFACES = {"lv_endo": LV_ENDO, "lv_epi": LV_EPI, "rv_endo": RV_ENDO, "rv_epi": RV_EPI}


def corner_jacobians(x):
    """Scaled Jacobians at the 8 corners of hexahedra x (n, 8, 3) -> (n, 8)."""
    e = x[:, CORNER_NEIGHBOURS, :] - x[:, :, None, :]
    e = e / np.maximum(np.linalg.norm(e, axis=-1, keepdims=True), 1e-300)
    return np.linalg.det(e)


def constraints(x):
    """The surfaces a node lies on: names of SURFACES and "base"."""
    on = [name for name, e in SURFACES.items() if abs(level(e, x)) < 1e-9]
    if abs(x[2] - BASE_Z) < 1e-9:
        on.append("base")
    return on


def restore(x, on):
    """Put a moved node back on its surfaces (alternating projections onto a curve)."""
    base = "base" in on
    ellipsoids = [SURFACES[name] for name in on if name != "base"]
    if base:
        x = x.copy()
        x[2] = BASE_Z
    for _ in range(1 if len(ellipsoids) < 2 else 50):
        for e in ellipsoids:
            x = project(e, x, on_base=base)
    return x


def directions(x, on):
    """Unit directions a node may move in: 3D, its tangent plane or its curve's tangent."""
    normals = [normal(SURFACES[name], x) for name in on if name != "base"]
    if "base" in on:
        normals.append(np.array([0.0, 0.0, 1.0]))
    if not normals:
        return list(np.eye(3))
    if len(normals) == 1:
        n = normals[0]
        a = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
        a /= np.linalg.norm(a)
        return [a, np.cross(n, a)]
    if len(normals) == 2:
        t = np.cross(normals[0], normals[1])
        return [t / np.linalg.norm(t)]
    return []


def improve(nodes, cells, fixed=(), sweeps=60, step=1.0):
    """Raise the smallest scaled Jacobian by moving nodes one at a time (pattern search):
    interior nodes in 3D, surface nodes in their tangent plane, junction and base-ring nodes
    along their curve, each moved node put back on its exact surfaces; corner points (three
    surfaces) stay. A move is kept when it raises the smallest corner Jacobian of the cells
    around the node (or keeps it and raises their mean)."""
    nodes = nodes.copy()
    around = [[] for _ in nodes]
    for c, cell in enumerate(cells):
        for v in cell:
            around[v].append(c)
    around = [np.array(a) for a in around]
    on = [constraints(x) for x in nodes]
    fixed = set(fixed)

    def quality(v, x):
        saved = nodes[v].copy()
        nodes[v] = x
        q = corner_jacobians(nodes[cells[around[v]]])
        nodes[v] = saved
        return (q.min(), q.mean())

    h = step
    for _ in range(sweeps):
        moved = 0
        for v in range(len(nodes)):
            if v in fixed:
                continue
            dirs = directions(nodes[v], on[v])
            if not dirs:
                continue
            best = quality(v, nodes[v])
            best_x = None
            for d in dirs:
                for sign in (1, -1):
                    x = restore(nodes[v] + sign * h * d, on[v])
                    q = quality(v, x)
                    if q[0] > best[0] + 1e-12 or (q[0] >= best[0] - 1e-12 and q[1] > best[1] + 1e-9):
                        best, best_x = q, x
            if best_x is not None:
                nodes[v] = best_x
                moved += 1
        if moved == 0:
            h *= 0.5
            if h < 1e-3:
                break
    return nodes


HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def orient(nodes, cells):
    """Reorder cells with a negative volume (mirror bottom/top)."""
    out = []
    for c in cells:
        x = nodes[c]
        v = np.linalg.det(np.array([x[1] - x[0], x[3] - x[0], x[4] - x[0]]))
        out.append(c if v > 0 else [c[4], c[5], c[6], c[7], c[0], c[1], c[2], c[3]])
    return np.array(out)


def boundary_faces(nodes, cells, cavity):
    count = {}
    for c in cells:
        for f in HEX_FACES:
            key = tuple(sorted(c[f]))
            count.setdefault(key, [0, [int(v) for v in c[f]]])[0] += 1
    cavity_faces = {tuple(sorted(np.asarray(c)[f])) for c in cavity for f in HEX_FACES}
    parts = {1: [], 2: [], 3: [], 4: []}
    lv_endo = lambda x: abs(level(LV_ENDO, x)) < 1e-9  # noqa: E731
    for key, (n, face) in count.items():
        if n != 1:
            continue
        x = nodes[face]
        if np.all(np.abs(x[:, 2] - BASE_Z) < 1e-9):
            parts[4].append(face)
        elif key in cavity_faces:
            parts[2].append(face)
        elif all(lv_endo(p) for p in x):
            parts[1].append(face)
        else:
            parts[3].append(face)
    return parts


def write_msh(path, nodes, cells, parts):
    names = {1: "lv_endocardium", 2: "rv_endocardium", 3: "epicardium", 4: "base"}
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "5"]
    lines += [f'2 {t} "{n}"' for t, n in names.items()] + ['3 1 "myocardium"', "$EndPhysicalNames"]
    lines += ["$Nodes", str(len(nodes))]
    # Rounded to 1e-9 mm (the optimisation leaves round-off of 1e-15 where a coordinate is
    # zero), so that a rerun writes the same file.
    lines += [f"{k + 1} " + " ".join(f"{round(c, 9) + 0.0:.12g}" for c in x)
              for k, x in enumerate(nodes)]
    lines += ["$EndNodes", "$Elements"]
    elements = []
    for tag in sorted(parts):
        for f in parts[tag]:
            elements.append(f"3 2 {tag} {tag} " + " ".join(str(v + 1) for v in f))
    for c in cells:
        elements.append("5 2 1 1 " + " ".join(str(v + 1) for v in c))
    lines += [str(len(elements))] + [f"{k + 1} {e}" for k, e in enumerate(elements)]
    lines += ["$EndElements", ""]
    Path(path).write_text("\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cells", type=int, default=10,
                        help="cells along the junction's chord round the RV bottom (even): "
                        "N - 2 columns of the RV free wall over its cavity")
    parser.add_argument("--rows", type=int, default=0,
                        help="ring rows from the apical cap to the base (default: 0.8 x cells)")
    parser.add_argument("--lv-layers", type=int, default=2, help="cells across the LV wall")
    parser.add_argument("--cap", type=int, default=0,
                        help="cells of the apical cap across the chord (default 0.3 x cells)")
    parser.add_argument("--corner", type=float, default=0.35,
                        help="where the junction's arms end, as a fraction of its length")
    parser.add_argument("--free-below", type=float, default=0.3,
                        help="cavity-wall nodes move only in cells whose scaled Jacobian is "
                        "below this")
    parser.add_argument("--no-improve", action="store_true",
                        help="skip the node optimisation (the constructed positions)")
    parser.add_argument("--base-z", type=float, default=BASE_Z,
                        help="height of the base plane [mm] (the LV cavity ellipsoid is centred "
                        "at z = 0 with its apex at z = -32.5; default: the cardiac-geometries "
                        "shape's 25, where the LV narrows to 64 %% of its width)")
    parser.add_argument("--lv-wall", type=float, default=LV_WALL,
                        help="thickness of the LV wall [mm] (default 5)")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    if args.cells % 2:
        parser.error("--cells must be even")
    if not (-LV_ENDO[1][2] < args.base_z < LV_ENDO[1][2]) or args.lv_wall <= 0:
        parser.error("--base-z must lie between the LV cavity's apex (-32.5) and its top (32.5) "
                     "and --lv-wall must be > 0")
    set_shape(args.base_z, args.lv_wall)
    rows = args.rows or round(0.8 * args.cells)
    nodes, cells, cavity = build(args.cells, rows, args.lv_layers, args.corner, args.cap)
    cells = orient(nodes, cells)
    if not args.no_improve:
        # The cavity walls keep the constructed nodes (on their surfaces, spread as built:
        # sliding them freely coarsens the polyhedral cavities) except in the cells of poor
        # quality (the corners of the junctions); the rest moves.
        parts = boundary_faces(nodes, cells, cavity)
        poor = corner_jacobians(nodes[cells]).min(axis=1) < args.free_below
        movable = {int(v) for cell in cells[poor] for v in cell}
        fixed = {int(v) for tag in (1, 2) for face in parts[tag] for v in face} - movable
        nodes = improve(nodes, cells, fixed)
    parts = boundary_faces(nodes, cells, cavity)
    write_msh(args.output, nodes, cells, parts)
    from systole_post.gmsh_mesh import read_msh, scaled_jacobians

    sj = scaled_jacobians(read_msh(args.output))
    print(f"wrote {args.output}: {len(cells)} hexahedra, {len(nodes)} nodes, "
          + ", ".join(f"{k} {len(v)} faces" for k, v in parts.items())
          + f"; scaled Jacobian min {sj.min():.3f}, mean {sj.mean():.3f}, "
          f"{np.sum(sj < 0.2)} cells < 0.2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
