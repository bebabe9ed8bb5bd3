"""Regression cases: numbers pinned before the engine restructuring.

Each case is a function returning ``{name: value}`` (a float or a list of
floats).  ``pinned.json`` holds the values that the code before the
restructuring ("One engine, composable scenes") computed, written by
``python validation/regression/pin.py``; ``validation/test_regression.py``
recomputes them with the current code and compares within the tolerance
stated for each (``tolerances.py``, with the error model).

Inputs that a chaotic protocol would not reproduce at round-off (a FIRE
packing, a sheared state of the plane-shear cell) are stored as data files
beside this module, so that a case measures the code under test and not the
chaos of an earlier stage.  Only this module knows the API: when an import
moves, the call changes here and the pinned values stay.
"""

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
PACKING = HERE / "packing256.npz"       # make_packing(256, 0.90, seed=0), pre-engine code
SHEAR_STATE = HERE / "shear_state.npz"  # a stick state of a sheared 150-disk cell


# ------------------------------------------------------------------ chain

def chain_ramp():
    """Every event of the default ramp (F_x to 0.1, step 1e-3, bisection 1e-6)."""
    from fricstab.scenes.chain import ChainScene
    from fricstab.protocols.ramp import run_ramp
    res = run_ramp(ChainScene(), 0.1, 1e-3, tol=1e-6)
    return {"event_fx": [e.fx for e in res.events],
            "event_birth": [1.0 if e.kind == "birth" else 0.0 for e in res.events],
            "growth_at_0.1": float(res.growth[-1])}


def _ramped(fx):
    from fricstab.protocols.ramp import ramped_equilibrium
    from fricstab.scenes.chain import ChainScene
    return ramped_equilibrium(ChainScene(), fx)


def chain_equilibrium():
    """Newton equilibrium at F_x = 0.03 reached by the 1e-3 ramp, and its spectrum."""
    from fricstab.analysis.spectrum import decompose
    from fricstab.scenes.chain import ChainScene, forces_and_jacobian, mass_vector, wall_history
    scene = ChainScene().with_fx(0.03)
    st = _ramped(0.03)
    _, jac = forces_and_jacobian(scene, st)
    w = decompose(jac, mass_vector(scene), vectors=False).eigenvalues
    return {"q": st.q.ravel().tolist(), "t_wall": wall_history(scene, st)[:, 0].tolist(),
            "eig_real": w.real.tolist(), "eig_imag": np.abs(w.imag).tolist()}


def chain_growth():
    """Growth rate of the unstable mode at F_x = 0.03: Jacobian and dynamics."""
    from fricstab.scenes.chain import ChainScene
    from fricstab.protocols.growth import measure_growth
    g = measure_growth(ChainScene().with_fx(0.03), _ramped(0.03))
    return {"predicted": g.predicted, "measured": g.measured}


def chain_transverse():
    """Transverse frequency at F_x = 0 in the paper's units (Charan: 0.235)."""
    from fricstab.scenes.chain import ChainScene
    from fricstab.analysis.modes import transverse_mode
    return {"omega": transverse_mode(ChainScene(), _ramped(0.0)).omega}


# ------------------------------------------------------------------ packings

def packing_make():
    """make_packing at N = 64 and 256: contact count, box and positions."""
    from fricstab.scenes.packing import find_contacts, make_packing
    out = {}
    for n in (64, 256):
        p = make_packing(n, 0.90, seed=0)
        pairs, _ = find_contacts(p.pos, p.radius, p.box)
        out[f"contacts_{n}"] = float(len(pairs))
        out[f"box_{n}"] = p.box
        out[f"pos_{n}"] = p.pos.ravel().tolist()
    return out


def _backbone():
    from fricstab.scenes.packing import Packing
    from fricstab.scenes.packing_friction import backbone
    return backbone(Packing.load(PACKING))


def _frictional(bb, kt):
    """The backbone with Ishima's law at kT/kN = kt (0: frictionless hertz)."""
    from fricstab.scenes.packing_friction import frictional, material, with_kt
    fr = frictional(bb, with_kt(material("ishima"), kt))
    return fr.system, fr.state


def packing_rigidity():
    """G_A, G_NA (solve and mode sum) and step strain on the stored N = 256 packing."""
    from fricstab.analysis.rigidity import rigidity
    from fricstab.protocols.stepstrain import step_strain
    bb = _backbone()
    out = {"backbone_n": float(bb.n)}
    for kt in (1e-4, 1.0, 10.0):
        system, state = _frictional(bb, kt)
        r = rigidity(system, state, modes=True)
        s = step_strain(system, state, dgamma=1e-6)
        out[f"g_a_{kt:g}"] = r.g_a
        out[f"g_na_{kt:g}"] = r.g_na_solve
        out[f"g_na_modes_{kt:g}"] = r.g_na_modes
        out[f"g_step_{kt:g}"] = s.g
        out[f"g_step_error_{kt:g}"] = s.error
    out["g_frictionless"] = rigidity(*_frictional(bb, 0.0)).g
    return out


def packing_dos():
    """Rotational-peak exponent over kT/kN = 1e-8..1e-2 on the stored packing."""
    from fricstab.analysis.dos import participation, rotational_peak, spectrum
    from fricstab.analysis.rigidity import linear_response
    bb = _backbone()
    kts = np.array([1e-8, 1e-6, 1e-4, 1e-2])
    med, low = [], []
    for kt in kts:
        jac = linear_response(*_frictional(bb, kt)).jacobian
        sp = spectrum(jac)
        _, psi_r, _ = participation(sp.right, 3)
        med.append(float(rotational_peak(sp.omega[2:], psi_r[2:])[1]))
        low.append(float(np.sort(sp.omega)[2]))
    slope = np.polyfit(np.log10(kts), np.log10(med), 1)[0]
    return {"exponent": float(slope), "peak": med, "lowest_omega": low}


def packing_dynamics():
    """Newtonian DEM with history (kT/kN = 1) on the stored packing, kicked: 2,000 steps."""
    from fricstab.analysis.packing_energy import energy
    from fricstab.engine import run
    from fricstab.scenes.packing import Packing
    from fricstab.scenes.packing_friction import material, packing_system
    p = Packing.load(PACKING)
    rng = np.random.default_rng(1)
    v = 1e-3 * rng.standard_normal((p.n, 3))
    system = packing_system(p, material("ishima", kt=1.0), skin=0.1)
    st = system.state(p.pos)
    st.v[:] = v          # (v_x, v_y, v_l), v_l = R omega: Ishima's coordinates
    e0 = energy(system, st)
    run(system, st, 0.02, 2000)
    return {"energy_start": e0, "energy_end": energy(system, st), "rebuilds": float(st.rebuilds),
            "q_end": st.q.ravel().tolist()}


# ------------------------------------------------------------------ plane shear

def shear_spectrum():
    """Spectrum of the stored stick state (a history on its cap is on the slide branch).

    The stored histories were put on their caps by the kernels of the run,
    to the bit; kernels that compute the cap differently at round-off (the
    contact-width solve of issue 16 moves lam by an ulp) would put a few of
    them an ulp inside it.  So the recorded branch is restored as for a
    frame (flags, CAP_REL; fricstab.analysis.shear_spectrum): a history is
    on its cap where ``|ft| = mu_s F_n`` (``|mr| = mu_r R_r F_n``) with the
    stored elastic normal force, to 1e-12 relative; in this state those
    ratios are 1 to 1 ulp and every other is at least 5e-3 from 1.
    """
    from fricstab.analysis.shear_spectrum import clamped_system, recorded_state, spectrum
    with np.load(SHEAR_STATE) as z:
        s = {k: z[k] for k in z.files}
    law = {"E": float(s["E"]), "nu": float(s["nu"]), "mus": float(s["mus"]),
           "mur": float(s["mur"])}
    system = clamped_system("lee_hurley", law, s["radius"], s["mass"], s["inertia"], s["kind"],
                            float(s["lx"]))
    ri, rj = (s["radius"][s["contacts"][:, k]] for k in (0, 1))
    on_t = np.abs(s["ft"]) >= law["mus"] * s["fn"] * (1.0 - 1e-12)
    on_r = np.abs(s["mr"]) >= law["mur"] * ri * rj / (ri + rj) * s["fn"] * (1.0 - 1e-12)
    state = recorded_state(system, s["pos"], s["angle"], s["contacts"],
                           np.column_stack([s["ft"], s["mr"]]),
                           flags=on_t.astype(np.int64) + 2 * on_r.astype(np.int64))
    spec = spectrum(system, state)
    w = spec.eigenvalues
    return {"n_sliding": float(spec.n_sliding), "n_rolling": float(spec.n_rolling),
            "n_complex_pairs": float(spec.n_complex_pairs),
            "max_growth_rate": spec.max_growth_rate,
            "eig_real": np.sort(w.real).tolist()}


CASES = {
    "chain_ramp": chain_ramp,
    "chain_equilibrium": chain_equilibrium,
    "chain_growth": chain_growth,
    "chain_transverse": chain_transverse,
    "packing_make": packing_make,
    "packing_rigidity": packing_rigidity,
    "packing_dos": packing_dos,
    "packing_dynamics": packing_dynamics,
    "shear_spectrum": shear_spectrum,
}
