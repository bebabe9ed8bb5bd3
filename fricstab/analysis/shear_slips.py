"""The Jacobian of the sheared packing at the stick state before each slip.

Beyond Lee & Hurley: for every slip phase (a maximal run of falling
``tau = S/N``, :func:`fricstab.analysis.shear.find_phases`) we take the output
frame just before it, where ``tau`` peaked, and compute the spectrum of
``D = -M^{-1} K`` of the bulk disks with the walls clamped
(:mod:`fricstab.analysis.shear_spectrum`: ``K = dF/dq`` from
:func:`fricstab.engine.jacobian` for the run's law, with the frame's
histories advanced by the law's increment rule, ``M`` the generalized
masses).  A stable real mode has ``lambda = omega^2 > 0``.  Recorded per
slip: the number of complex-conjugate pairs, the largest growth rate
``max |Re sqrt(-lambda)|`` (1/s) and the lowest real eigenvalue (1/s^2), the
k softest eigenvalues, the contacts on their tangential and rolling caps,
and the drop ``Delta tau_p`` of the slip that follows.

Route.  ``soft`` (default): the k eigenvalues of smallest modulus by
shift-invert ARPACK, and the statistics over those k only (pairs among the
k softest, the largest growth rate among them); ``dense``: every
eigenvalue, the statistics over the whole spectrum (pair counts of the
whole spectrum need it).  The module docstring of
:mod:`fricstab.analysis.shear_spectrum` states what each can report.  A
frame where ARPACK fails falls back to the dense eigenvalues in the same
window; the frames are listed in ``fallback`` and one warning says how many.

Contacts at a cap.  The frame records each contact's cap flags; the
histories are SI values converted from the run's reduced units, so a history
on its cap may sit a few ulp inside the cap recomputed from the SI positions.
The recorded branch is restored with the relative ``CAP_REL`` move of
:func:`fricstab.analysis.shear_spectrum.recorded_state` (the generated kernels
put a history exactly on its cap on the slide branch, so only this rounding
needs the move).

Units: SI per unit thickness, as the frames.
"""

import warnings
from dataclasses import dataclass

import numpy as np

from fricstab import signals
from fricstab.errors import ParameterError

__all__ = ["SCOPE", "SlipSpectra", "slip_spectra"]

#: What the statistics of each route run over (``summary()['statistics_over']``).
SCOPE = {"soft": "the {k} eigenvalues of smallest modulus (shift-invert ARPACK); pair counts "
                 "and growth rates of the whole spectrum need --spectra dense",
         "dense": "the whole spectrum (dense eigenvalues)"}


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
    softest : ndarray (S, k + 1) complex
        The k softest eigenvalues by modulus (k + 1 where a conjugate pair
        straddles the edge; NaN pads).
    n_null : ndarray (S,) int
        Degrees of freedom without stiffness (rattlers): exact zero eigenvalues.
    fallback : ndarray (S,) bool
        Soft route: ARPACK failed at that frame, the dense eigenvalues gave the window.
    route : str
        ``"soft"`` or ``"dense"``: what the statistics run over (module docstring).
    k : int
        The window.
    """

    frame: np.ndarray
    dtau_p: np.ndarray
    n_complex_pairs: np.ndarray
    max_growth_rate: np.ndarray
    lowest_real_eigenvalue: np.ndarray
    n_sliding: np.ndarray
    n_rolling: np.ndarray
    softest: np.ndarray
    n_null: np.ndarray
    fallback: np.ndarray
    route: str
    k: int

    def correlations(self):
        """Spearman of each statistic with the following Delta tau_p, overall and per bin."""
        from fricstab.analysis.shear_phases import binned_spearman, spearman_cell
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
            "route": self.route,
            "k": self.k,
            "statistics_over": SCOPE[self.route].format(k=self.k),
            "fallbacks_to_dense": int(self.fallback.sum()),
            "n_slips": s,
            "slips_with_complex_pairs": int((self.n_complex_pairs > 0).sum()),
            "n_complex_pairs_max": int(self.n_complex_pairs.max()) if s else None,
            "max_growth_rate_median_per_s": float(np.median(self.max_growth_rate)) if s else None,
            "lowest_real_eigenvalue_min": float(self.lowest_real_eigenvalue.min()) if s else None,
            "correlations_with_following_dtau_p": self.correlations(),
        }


def slip_spectra(frames, phases, dtau_p, params, progress=False, route="soft", k=None,
                 previous=None):
    """Spectrum statistics at the stick state before every slip (beyond Lee & Hurley).

    At the frame where tau peaked before every slip: the stiffness
    ``K = dF/dq`` of the bulk disks (walls clamped) from the verified blocks of
    the run's law, sliding and rolling contacts on their slide branch, and the
    spectrum of ``D = -M^-1 K``: its soft end by shift-invert ARPACK (default)
    or the whole spectrum (dense, up to 3,000 dof); module docstring.

    Parameters
    ----------
    frames : Frames
        The run's frames (SI).
    phases : ndarray, shape (P, 2)
        First and last step of each phase (:func:`find_phases`); step ``a``
        goes from frame ``a - 1`` to ``a``.
    dtau_p : ndarray, shape (P,)
        Delta tau_p per phase (Eq. 1; dimensionless); slips are the phases with
        ``dtau_p < 0``.
    params : dict
        The run's validated scene (``law``, ``law_params`` in SI).
    progress : bool
        tqdm bar.
    route : {"soft", "dense"}
        Soft end by ARPACK (default) or the whole spectrum.
    k : int, optional
        The window of softest eigenvalues (default
        :data:`fricstab.analysis.shear_spectrum.SOFT_K`).
    previous : mapping, optional
        The ``slip_*`` arrays of an earlier analysis of the first frames of
        these frames with the same route and k (checked by the caller,
        :func:`fricstab.analysis.shear.analyze`): a slip whose stick frame it
        holds takes its row instead of a new spectrum (a frame's spectrum
        depends on that frame only, so the result is the same to the bit).

    Returns
    -------
    SlipSpectra
        Per slip: ``frame``, ``dtau_p``, ``n_complex_pairs``,
        ``max_growth_rate`` (``max |Re sqrt(-lambda)|``, 1/s),
        ``lowest_real_eigenvalue`` (1/s^2), ``n_sliding``, ``n_rolling``;
        over the soft window only for ``route="soft"``.
    """
    from tqdm import tqdm

    from fricstab.analysis.shear_spectrum import (ROUTES, SOFT_K, check_window, clamped_system,
                                                  recorded_state, soft_spectrum, spectrum)
    if route not in ROUTES:
        raise ParameterError(f"route must be one of {ROUTES}, got {route!r}")
    k = SOFT_K if k is None else check_window(k)
    phases = np.asarray(phases, dtype=np.int64).reshape(-1, 2)
    dtau_p = np.asarray(dtau_p, dtype=float)
    if len(dtau_p) != len(phases):
        raise ParameterError(f"dtau_p has {len(dtau_p)} entries for {len(phases)} phases")
    for key in ("law", "law_params"):
        if key not in params:
            raise ParameterError(f"params: missing scene key {key!r} (a run made before the "
                                 "engine: rerun it)")
    system = clamped_system(params["law"], params["law_params"], frames.radius, frames.mass,
                            frames.inertia, frames.kind, frames.lx)
    slips = np.flatnonzero(dtau_p < 0)
    cols = {c: [] for c in ("n_complex_pairs", "max_growth_rate", "lowest_real_eigenvalue",
                            "n_sliding", "n_rolling", "n_null", "fallback")}
    soft = np.full((len(slips), k + 1), np.nan, complex)
    done = {} if previous is None else {int(f): r for r, f in enumerate(previous["slip_frame"])}
    for s, p in enumerate(tqdm(slips, desc=f"slip spectra ({route})", unit="slip",
                               disable=not progress)):
        signals.check()
        f = int(phases[p, 0]) - 1
        if f in done:
            r = done[f]
            for c in cols:
                v = previous[f"slip_{c}"][r]
                if c == "fallback":     # stored as a bool; the reason stayed in that analysis
                    v = "(reused)" if v else ""
                cols[c].append(v)
            soft[s] = previous["slip_softest"][r]
            continue
        ij, _, _, hist, flag = frames.contacts(f)
        state = recorded_state(system, frames.pos[f], frames.angle[f], ij, hist, flag)
        spec = soft_spectrum(system, state, k) if route == "soft" else spectrum(system, state, k)
        for c in cols:
            cols[c].append(getattr(spec, c))
        soft[s, :len(spec.softest)] = spec.softest
    reasons = cols.pop("fallback")
    fell = np.array([bool(r) for r in reasons], bool)
    if fell.any():
        first = int(np.flatnonzero(fell)[0])
        warnings.warn(f"slip spectra: ARPACK failed at {int(fell.sum())} of {len(slips)} frames "
                      f"(first: frame {int(phases[slips[first], 0]) - 1}, {reasons[first]}); "
                      "their window came from the dense eigenvalues (slip_fallback)",
                      RuntimeWarning, stacklevel=2)
    ints = ("n_complex_pairs", "n_sliding", "n_rolling", "n_null")
    return SlipSpectra(frame=phases[slips, 0] - 1, dtau_p=dtau_p[slips], softest=soft,
                       fallback=fell, route=route, k=int(k),
                       **{c: np.asarray(v, dtype=np.int64 if c in ints else float)
                          for c, v in cols.items()})
