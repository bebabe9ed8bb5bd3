"""The Jacobian of the sheared packing at the stick state before each slip.

Beyond Lee & Hurley: for every slip phase (a maximal run of falling
``tau = S/N``, :func:`fricstab.analysis.shear.find_phases`) we take the output
frame just before it, where ``tau`` peaked, and compute the spectrum of
``D = -M^{-1} K`` of the bulk disks with the walls clamped
(:func:`fricstab.analysis.shear_spectrum.shear_spectrum`; ``K = dF/dq`` from the
verified ``lee_hurley`` blocks, the histories advanced by the law's increment
rule).  A stable real mode has ``lambda = omega^2 > 0``.  Recorded per slip:
the number of complex-conjugate pairs, the largest growth rate
``max |Re sqrt(-lambda)|`` (1/s) and the lowest real eigenvalue (1/s^2), and
the drop ``Delta tau_p`` of the slip that follows.

Contacts at a cap.  A contact whose stored history sits on its Coulomb (or
rolling) cap is on the slide branch of the law: its Jacobian is the cap's
derivative ``mu dF_n/dq``.  The stored value equals the cap only to the
rounding of the SI conversion, so a history within a relative ``CAP_REL`` of
its cap is moved just outside it (by the same ``CAP_REL``) before the kernel
decides the branch.  The force changes by ``CAP_REL`` of the cap at most:
far below the tolerance of anything derived from it.

Units: SI per unit thickness, as the frames.
"""

from dataclasses import dataclass

import numpy as np

from fricstab.laws import ParameterError

__all__ = ["CAP_REL", "SlipSpectra", "on_slide_branch", "slip_spectra"]

#: Relative distance to a cap within which a stored history counts as on it.
CAP_REL = 1e-9


@dataclass(frozen=True)
class SlipSpectra:
    """Per slip: frame before it, its drop, and the spectrum statistics.

    Attributes
    ----------
    frame : ndarray (S,) int
        Output frame of the stick state (the frame before the slip's first step).
    dtau_p : ndarray (S,)
        Delta tau_p of the slip that follows (negative).
    n_complex_pairs, max_growth_rate, lowest_real_eigenvalue : ndarray (S,)
        Statistics of ``D = -M^{-1} K`` at that frame (1/s, 1/s^2).
    n_sliding, n_rolling : ndarray (S,) int
        Contacts on the tangential and rolling slide branch at that frame.
    """

    frame: np.ndarray
    dtau_p: np.ndarray
    n_complex_pairs: np.ndarray
    max_growth_rate: np.ndarray
    lowest_real_eigenvalue: np.ndarray
    n_sliding: np.ndarray
    n_rolling: np.ndarray

    def correlations(self):
        """Spearman of each statistic with the following Delta tau_p, overall and per bin."""
        from fricstab.analysis.shear import binned_spearman, spearman_cell
        stats = {"n_complex_pairs": self.n_complex_pairs,
                 "max_growth_rate": self.max_growth_rate,
                 "lowest_real_eigenvalue": self.lowest_real_eigenvalue}
        return {"all": {k: spearman_cell(self.dtau_p, v) for k, v in stats.items()},
                "binned": binned_spearman(self.dtau_p, stats)}

    def arrays(self):
        """Arrays for an NPZ file, prefixed ``slip_``."""
        return {f"slip_{k}": getattr(self, k) for k in self.__dataclass_fields__}

    def summary(self):
        """JSON-able summary: counts, ranges and the correlations."""
        s = len(self.frame)
        return {
            "n_slips": s,
            "slips_with_complex_pairs": int((self.n_complex_pairs > 0).sum()),
            "n_complex_pairs_max": int(self.n_complex_pairs.max()) if s else None,
            "max_growth_rate_median_per_s": float(np.median(self.max_growth_rate)) if s else None,
            "lowest_real_eigenvalue_min": float(self.lowest_real_eigenvalue.min()) if s else None,
            "correlations_with_following_dtau_p": self.correlations(),
        }


def on_slide_branch(ft, mr, fn, radius_i, radius_j, mu_s, mu_r):
    """Histories moved just outside their caps where they sit on them (module docstring).

    Returns ``(ft, mr, sliding, rolling)``; the inputs are not modified.
    """
    ft, mr, fn = (np.array(a, dtype=float) for a in (ft, mr, fn))
    r_r = radius_i * radius_j / (radius_i + radius_j)
    caps = ((ft, mu_s * fn), (mr, mu_r * r_r * fn))
    flags = []
    for h, cap in caps:
        on = (cap > 0) & (np.abs(h) >= (1.0 - CAP_REL) * cap)
        h[on] = np.sign(h[on]) * cap[on] * (1.0 + CAP_REL)
        flags.append(on)
    return ft, mr, flags[0], flags[1]


def slip_spectra(frames, phases, dtau_p, params, progress=False):
    """Spectrum statistics at the stick state before every slip (module docstring).

    Parameters
    ----------
    frames : Frames
        The run's frames (SI).
    phases : ndarray (P, 2)
        First and last step of each phase (:func:`find_phases`); step ``a``
        goes from frame ``a - 1`` to ``a``.
    dtau_p : ndarray (P,)
        Delta tau_p per phase; slips are the phases with ``dtau_p < 0``.
    params : dict
        The run's scene: ``E``, ``nu``, ``mu_s``, ``mu_r``.
    progress : bool
        tqdm bar.
    """
    from tqdm import tqdm

    from fricstab.analysis.shear_spectrum import shear_spectrum
    phases = np.asarray(phases, dtype=np.int64).reshape(-1, 2)
    dtau_p = np.asarray(dtau_p, dtype=float)
    if len(dtau_p) != len(phases):
        raise ParameterError(f"dtau_p has {len(dtau_p)} entries for {len(phases)} phases")
    for key in ("E", "nu", "mu_s", "mu_r"):
        if key not in params:
            raise ParameterError(f"params: missing scene key {key!r}")
    estar = params["E"] / (2.0 * (1.0 - params["nu"] ** 2))
    slips = np.flatnonzero(dtau_p < 0)
    mobile = frames.kind == 0
    cols = {k: [] for k in ("n_complex_pairs", "max_growth_rate", "lowest_real_eigenvalue",
                            "n_sliding", "n_rolling")}
    for p in tqdm(slips, desc="slip spectra", unit="slip", disable=not progress):
        k = int(phases[p, 0]) - 1
        ij, _, fn, ft, mr, _ = frames.contacts(k)
        ft, mr, sl, ro = on_slide_branch(ft, mr, fn, frames.radius[ij[:, 0]],
                                         frames.radius[ij[:, 1]], params["mu_s"],
                                         params["mu_r"])
        spec = shear_spectrum(frames.pos[k], frames.angle[k], frames.radius, frames.mass,
                              frames.inertia, mobile, ij, ft, mr, frames.lx, estar,
                              params["nu"], params["mu_s"], params["mu_r"])
        for key, value in (("n_complex_pairs", spec.n_complex_pairs),
                           ("max_growth_rate", spec.max_growth_rate),
                           ("lowest_real_eigenvalue", spec.lowest_real_eigenvalue),
                           ("n_sliding", int(sl.sum())), ("n_rolling", int(ro.sum()))):
            cols[key].append(value)
    ints = ("n_complex_pairs", "n_sliding", "n_rolling")
    return SlipSpectra(frame=phases[slips, 0] - 1, dtau_p=dtau_p[slips],
                       **{k: np.asarray(v, dtype=np.int64 if k in ints else float)
                          for k, v in cols.items()})
