"""Tolerances of the regression cases, each with its error model.

``TOLERANCES[case][key] = (kind, value, reason)`` with ``kind``:

* ``"exact"``: equal;
* ``"abs"``: ``max |new - pinned| <= value``;
* ``"rel"``: ``max |new - pinned| <= value * max |pinned|``;
* ``"abs_key"``: ``max |new - pinned| <= pinned[value]`` (a bound the case itself reports).

Keys absent here are not compared (they are recorded for the reader).
"""

EPS = 2.220446049250313e-16

TOLERANCES = {
    "chain_ramp": {
        "event_birth": ("exact", 0, "the kinds of the events in order"),
        "event_fx": ("abs", 1e-6, "bisection bracket 1e-6: a round-off change of the pair "
                     "indicator D can move the final bracket by at most its width"),
        "growth_at_0.1": ("rel", 1e-8, "Im sqrt(-lambda) of a matrix that changes at "
                          "round-off, eigenvalue condition < 1e6"),
    },
    "chain_equilibrium": {
        "q": ("abs", 1e-12, "Newton to max|F| < 1e-12 against stiffness ~100 leaves 1e-14 in "
              "q; the history path differs at round-off per step (~30 steps x 5 iterations)"),
        "t_wall": ("abs", 1e-12, "as q"),
        "eig_real": ("rel", 1e-8, "eigenvalues of a Jacobian perturbed at 1e-14, condition "
                     "numbers below 1e6 away from exceptional points"),
        "eig_imag": ("rel", 1e-8, "as eig_real"),
    },
    "chain_growth": {
        "predicted": ("rel", 1e-8, "as the chain spectrum"),
        "measured": ("rel", 2e-3, "the dynamics may advance the history with the increment "
                     "rule at the other end of the step (O(dt) in the discrete dynamics); "
                     "the growth test's own error model is 1e-3 against the Jacobian"),
    },
    "chain_transverse": {
        "omega": ("rel", 1e-10, "eigenvalue of a near-diagonal matrix, round-off"),
    },
    "packing_make": {
        "contacts_64": ("exact", 0, "same contact network"),
        "contacts_256": ("exact", 0, "same contact network (measured with the pairs summed in "
                         "key order instead of search order)"),
        "box_64": ("rel", 1e-15, "closed form of phi"),
        "box_256": ("rel", 1e-15, "closed form of phi"),
        "pos_64": ("abs", 1e-6, "FIRE amplifies round-off of the force summation order; the "
                   "same minimum is reached"),
        "pos_256": ("abs", 1e-3, "FIRE near jamming: with the pairs summed in key order the same "
                    "minimum is reached to 3.7e-5 (measured); at N >= 1024 another minimum "
                    "(2454 vs 2474 contacts, measured), so those packings are not pinned"),
    },
    "packing_rigidity": {
        "backbone_n": ("exact", 0, "rattler removal is combinatorial"),
        "g_frictionless": ("rel", 1e-9, "same J and Xi summed in another order: eps cond(J)"),
        **{f"{q}_{kt}": ("rel", 1e-9, "same J and Xi summed in another order: eps cond(J); "
                          "mode sum and solve agree to 1e-13")
           for q in ("g_a", "g_na", "g_na_modes") for kt in ("0.0001", "1", "10")},
        **{f"g_step_{kt}": ("abs_key", f"g_step_error_{kt}", "the step-strain error model "
                            "(truncation + round-off / dgamma) bounds any change of its path")
           for kt in ("0.0001", "1", "10")},
    },
    "packing_dos": {
        "exponent": ("abs", 1e-6, "fit of bin centres that do not move under round-off"),
        "peak": ("rel", 1e-9, "the median omega of the rotation-dominated modes, not a bin "
                 "centre: an eigenvalue moves by ~eps |J| (|J| ~ 10 t0^-2) under another "
                 "summation order (BLAS threads), omega = sqrt(lambda) by eps |J| / (2 omega) "
                 "= 1.5e-11 at the smallest median 7.6e-5; 1e-9 of the largest (7.6e-2) bounds "
                 "it 5-fold (measured: 1.2e-13 between 1 and 2 BLAS threads)"),
        "lowest_omega": ("rel", 1e-6, "smallest nonzero eigenvalue: eps max/min relative"),
    },
    "packing_dynamics": {
        "energy_start": ("rel", 1e-12, "a sum over contacts in another order"),
        "energy_end": ("rel", 1e-9, "2,000 Verlet steps (40 t0) amplify round-off modestly"),
        "q_end": ("abs", 1e-9, "as energy_end"),
        "rebuilds": ("exact", 0, "no particle moves half the skin"),
    },
    "shear_spectrum": {
        "n_sliding": ("exact", 0, "branch decision with the CAP_REL margin"),
        "n_rolling": ("exact", 0, "as n_sliding"),
        "n_complex_pairs": ("exact", 0, "threshold 1e-8 of the radius, far above round-off"),
        "max_growth_rate": ("rel", 1e-6, "Re sqrt(-lambda) of a dense spectrum at round-off"),
        "eig_real": ("rel", 1e-8, "eigenvalues at round-off x condition"),
    },
}
