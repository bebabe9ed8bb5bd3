"""The transverse (y) eigenmode of the chain and the backward-wave prediction.

Charan et al. identify, among the 3N eigenvectors of J, one that is a pure
y transverse wave (no x or theta projection, their Fig. 6), with frequency
omega ~ 0.235 and wavelength ~2 (in 2R), and predict the backward sliding
wave speed V2 = omega / k.  Here: the right eigenvector of M^-1 J with the
largest fraction of its norm on the y coordinates, its frequency
``sqrt(-lambda)``, its dominant wavelength along the ring (discrete Fourier
transform of the y components, period 2NR) and ``omega / k``; all in the
paper's units (length 2R, time sqrt(m 2R / kn)).

That single pick is fragile: the y band is nearly degenerate (at F_x = 0
exactly: neighbours only touch, so the ten y modes are uncoupled), and
which of its members has the largest y fraction decides the wavelength.
:func:`transverse_band` resolves the whole band by wavelength instead
(every mode's Fourier content along the ring, and each wavelength's
frequency), so the paper's "wavelength approximately 2" mode can be named:
``transverse_band(scene, state).mode(2.0)``.
"""

from dataclasses import dataclass, replace

import numpy as np

from fricstab.analysis.spectrum import decompose
from fricstab.errors import ParameterError
from fricstab.scenes.chain import (check_chain, check_convention, eigenvalue_unit,
                                   forces_and_jacobian, mass_vector)

__all__ = ["BandMode", "EQUILIBRIUM_TOL", "TransverseBand", "TransverseMode",
           "fourier_power", "resolve_band", "transverse_band", "transverse_mode"]

#: A state is taken as an equilibrium where max |F| <= EQUILIBRIUM_TOL * F_y (the Newton
#: ramp leaves ~1e-12 absolute, 1e-11 F_y; a perturbed or unrelaxed state is off by >1e-3 F_y).
EQUILIBRIUM_TOL = 1e-6
#: Eigenvalues closer than this (relative to max |lambda|) form one degenerate cluster
#: (rounding of LAPACK on a 3N = 30 matrix is ~1e-14; true splittings in the band >1e-4).
CLUSTER_TOL = 1e-9


@dataclass(frozen=True)
class TransverseMode:
    """The most transverse eigenmode, in the paper's units."""

    y_fraction: float     # |v_y|^2 / |v|^2 of the right eigenvector
    omega: float          # sqrt(-lambda) in paper time units
    wavelength: float     # in units of 2R
    speed: float          # omega / k, paper units (2R per time unit)
    vector: np.ndarray    # the right eigenvector, (N, dof) real (generalized coordinates)


def transverse_mode(scene, state, convention="physical"):
    """The chain's transverse mode: the real eigenmode with the largest y fraction.

    Charan compare the backward sliding wave V2 with the phase speed of this
    mode (Sec. IV); at F_x = 0 its frequency is 0.235 in their units.

    Parameters
    ----------
    scene : ChainScene
    state : State
        An equilibrium of the chain.
    convention : str
        The mass matrix of the spectrum (:data:`fricstab.scenes.chain.CONVENTIONS`).

    Returns
    -------
    TransverseMode
        ``y_fraction`` (``|v_y|^2 / |v|^2`` of the right eigenvector),
        ``omega`` (``sqrt(-lambda)`` in paper time units ``sqrt(m 2R/k_n)``),
        ``wavelength`` (units of 2R), ``speed`` (``omega / k``, 2R per paper
        time unit) and ``vector`` (N, dof).
    """
    check_chain(scene, state)
    check_convention(convention)
    _, jac = forces_and_jacobian(scene, state)
    spec = decompose(jac, mass_vector(scene, convention))
    n, dof = scene.n, scene.dof
    best, best_frac = None, -1.0
    for k, lam in enumerate(spec.eigenvalues):
        if lam.imag != 0 or lam.real >= 0:
            continue
        v = spec.right[:, k].real.reshape(n, dof)
        frac = float((v[:, 1] ** 2).sum() / (v ** 2).sum())
        if frac > best_frac:
            best, best_frac = (k, v), frac
    if best is None:
        raise ParameterError("the state has no real oscillating mode (no real lambda < 0)")
    k, v = best
    length = 2 * scene.radius
    omega = float(np.sqrt(-spec.eigenvalues[k].real * eigenvalue_unit(scene, convention)))
    amp = np.abs(np.fft.rfft(v[:, 1]))
    amp[0] = 0.0  # a uniform y motion has no wavelength
    m = int(np.argmax(amp)) if amp.max() > 0 else 0
    ring = scene.period / length
    wavelength = ring / m if m else np.inf
    wavenumber = 2 * np.pi / wavelength
    return TransverseMode(best_frac, omega, float(wavelength), float(omega / wavenumber), v)


@dataclass(frozen=True)
class BandMode:
    """One mode of the transverse band, in the paper's units (length 2R, time t_0)."""

    omega: float          # sqrt(-lambda * eigenvalue_unit)
    y_fraction: float     # |v_y|^2 / |v|^2
    m: int                # the Fourier index asked for (0..N/2)
    wavelength: float     # N / m in 2R (inf for m = 0)
    purity: float         # share of the y power in Fourier family m
    dominant: bool        # m is the mode's dominant family
    speed: float          # omega / k, k = 2 pi m / N (inf for m = 0)


@dataclass(frozen=True)
class TransverseBand:
    """The chain's y band resolved by wavelength (:func:`transverse_band`).

    Per mode (sorted by omega): ``omega``, ``y_fraction``, ``m``, ``purity``
    and ``power`` (modes x (N//2 + 1), each row the mode's y power per Fourier
    family, summing to 1); per Fourier index m: ``omega_by_m`` (the y-power
    weighted mean omega of the band's modes, NaN where the band has no power in m).
    ``n`` is the ring's length in 2R (the number of disks).
    """

    n: int
    convention: str
    omega: np.ndarray
    y_fraction: np.ndarray
    m: np.ndarray
    purity: np.ndarray
    power: np.ndarray
    omega_by_m: np.ndarray

    @property
    def wavenumber(self):
        """k = 2 pi m / N of each mode (1/(2R))."""
        return 2 * np.pi * self.m / self.n

    @property
    def wavelength(self):
        """N / m of each mode (2R; inf for m = 0)."""
        with np.errstate(divide="ignore"):
            return self.n / self.m.astype(float)

    def mode(self, wavelength=2.0):
        """The band mode that carries most of the band's y power at ``wavelength`` (2R).

        The mode maximizing ``y_fraction * power[:, m]`` for the Fourier family m of
        ``wavelength`` (which must be N / m, m in 0..N/2; inf for m = 0), as a
        BandMode: ``purity`` is its share of y power in m, ``dominant`` whether m
        is its dominant family (False: no eigenvector is mainly that wavelength),
        ``speed`` its omega / k.  For the band's frequency of the wavelength see
        :meth:`frequency` and :meth:`speed`.
        """
        m = self._index(wavelength)
        pick = int(np.argmax(self.power[:, m] * self.y_fraction))
        k = 2 * np.pi * m / self.n
        omega = float(self.omega[pick])
        return BandMode(omega, float(self.y_fraction[pick]), m, float(self.n / m) if m else np.inf,
                        float(self.power[pick, m]), bool(self.m[pick] == m),
                        omega / k if m else np.inf)

    def frequency(self, wavelength=2.0):
        """``omega_by_m`` of ``wavelength`` (2R): the band's y-power weighted omega there."""
        return float(self.omega_by_m[self._index(wavelength)])

    def speed(self, wavelength=2.0):
        """Predicted phase speed ``frequency(wavelength) / k`` (2R / t_0), k = 2 pi / wavelength."""
        return self.frequency(wavelength) * float(wavelength) / (2 * np.pi)

    def _index(self, wavelength):
        if not isinstance(wavelength, (int, float, np.integer, np.floating)) or \
                np.isnan(wavelength) or wavelength <= 0:
            raise ParameterError(f"wavelength must be a positive number (2R), got {wavelength!r}")
        m = 0 if np.isinf(wavelength) else self.n / float(wavelength)
        if abs(m - round(m)) > 1e-9 * self.n or not 0 <= round(m) <= self.n // 2:
            raise ParameterError(f"wavelength {wavelength!r} is not N/m for m = 0..{self.n // 2} "
                                 f"on a ring of N = {self.n}")
        return int(round(m))


def fourier_power(y):
    """Share of ``y``'s power (columns: modes) in each Fourier family m = 0..N/2 along the ring.

    Family m holds the ring's cosine and sine of wavenumber 2 pi m / N (m and
    N - m: the same wavelength N/m), so each column of the result sums to 1.
    """
    y = np.asarray(y, dtype=float)
    n = y.shape[0]
    p = np.abs(np.fft.rfft(y, axis=0)) ** 2
    p[1:(n + 1) // 2] *= 2.0  # m and N - m; m = 0 and (even N) m = N/2 are single
    total = p.sum(axis=0)
    return p / np.where(total > 0, total, 1.0)


def _shift_operator(n, dof):
    """(T + T^-1) / 2 on the generalized coordinates: T moves every dof by one disk."""
    t = np.kron(np.roll(np.eye(n), 1, axis=0), np.eye(dof))
    return (t + t.T) / 2


def _resolve_clusters(w, vec, n, dof):
    """Rotate each degenerate cluster of real eigenvalues to the eigenvectors of (T + T^-1)/2.

    Within a cluster any basis is one of eigenvectors; this one is Fourier-pure
    where the ring's translation is a symmetry (F_x = 0) and the Ritz choice elsewhere.
    """
    vec = vec.copy()
    scale = np.abs(w).max()
    order = np.argsort(w)
    shift = _shift_operator(n, dof)
    start = 0
    while start < len(order):
        end = start + 1
        while end < len(order) and w[order[end]] - w[order[end - 1]] <= CLUSTER_TOL * scale:
            end += 1
        idx = order[start:end]
        if len(idx) > 1:
            q, _ = np.linalg.qr(vec[:, idx])
            _, rot = np.linalg.eigh(q.T @ shift @ q)
            vec[:, idx] = q @ rot
        start = end
    return vec


def resolve_band(jac, mass, n, dof, unit=1.0, size=None):
    """The transverse band of a ring's ``M^-1 J``, resolved by wavelength.

    The band: the ``size`` (default n) real oscillating modes (real lambda < 0)
    with the largest y fraction ``|v_y|^2 / |v|^2`` of their right eigenvector
    (dof order x, y[, theta] per disk; n disks spaced 2R on a ring of n 2R).

    Criterion.  Each mode's wavelength is its dominant Fourier family m of
    the y components (:func:`fourier_power`; the disks' index along the ring is
    the coordinate), its purity the share of the y power in m.  A degenerate
    cluster (eigenvalues within CLUSTER_TOL) has no preferred basis: it is
    rotated to diagonalize the ring's shift (T + T^-1)/2 within the cluster,
    which makes the modes Fourier-pure wherever translation is a symmetry.
    Each wavelength's frequency ``omega_by_m`` is the mean omega of the band's
    modes weighted by their y power in family m (basis-independent within a
    degenerate cluster); near-degenerate modes that mix wavelengths are kept
    as the eigenvectors are, their mixing shown by purity < 1.

    Parameters
    ----------
    jac : ndarray (n dof, n dof)
        dF/dq (force/length).
    mass : ndarray (n dof,)
        Generalized masses.
    n, dof : int
        Disks and dof per disk (y is dof 1).
    unit : float
        Factor putting an eigenvalue in the paper's units (``eigenvalue_unit``).
    size : int, optional
        Number of modes in the band (default n).

    Returns
    -------
    TransverseBand
        With ``convention`` empty (:func:`transverse_band` names it).
    """
    spec = decompose(jac, mass)
    real = np.flatnonzero((spec.eigenvalues.imag == 0) & (spec.eigenvalues.real < 0))
    if real.size == 0:
        raise ParameterError("the state has no real oscillating mode (no real lambda < 0)")
    w = spec.eigenvalues[real].real
    vec = _resolve_clusters(w, spec.right[:, real].real, n, dof)
    vec = vec / np.linalg.norm(vec, axis=0)
    y = vec.reshape(n, dof, -1)[:, 1, :]
    yfrac = (y ** 2).sum(axis=0)
    band = np.argsort(-yfrac, kind="stable")[:size or n]
    omega = np.sqrt(-w[band] * unit)
    order = np.argsort(omega, kind="stable")
    band, omega = band[order], omega[order]
    power = fourier_power(y[:, band]).T
    m = np.argmax(power, axis=1)
    weight = power * yfrac[band, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        by_m = (weight * omega[:, None]).sum(axis=0) / weight.sum(axis=0)
    by_m[weight.sum(axis=0) <= 1e-12 * weight.sum()] = np.nan
    return TransverseBand(n, "", omega, yfrac[band], m, power[np.arange(len(m)), m], power, by_m)


def transverse_band(scene, state, convention="physical"):
    """The chain's transverse (y) band at an equilibrium, resolved by wavelength.

    Charan et al. (Fig. 6) pick "a pure y transverse wave" of omega ~ 0.235
    and "wavelength approximately 2" (2R) and predict the backward sliding
    wave speed V2 = omega / k ~ 0.235 / pi.  Here: the N real oscillating
    modes of ``M^-1 J`` with the largest y fractions, each with its wavelength
    and purity (:func:`resolve_band` states the criterion); ``.mode(2.0)`` is
    the paper's mode and its ``speed`` the predicted V2.

    Parameters
    ----------
    scene : ChainScene
    state : State
        An equilibrium of the chain (max |F| <= EQUILIBRIUM_TOL F_y).
    convention : str
        The mass matrix (:data:`fricstab.scenes.chain.CONVENTIONS`).

    Returns
    -------
    TransverseBand
        omega in the paper's units ``1/t_0``, t_0 = sqrt(m 2R / k_n); k in 1/(2R).

    Raises
    ------
    ParameterError
        Not a chain scene and state, an unknown convention, a state that is not
        an equilibrium, or no real oscillating mode.
    """
    check_chain(scene, state)
    check_convention(convention)
    force, jac = forces_and_jacobian(scene, state)
    residual = float(np.abs(force).max())
    if not residual <= EQUILIBRIUM_TOL * scene.fy:
        raise ParameterError(f"state is not an equilibrium: max |F| = {residual:.3g} > "
                             f"{EQUILIBRIUM_TOL:g} F_y (relax it first, e.g. ramped_equilibrium)")
    band = resolve_band(jac, mass_vector(scene, convention), scene.n, scene.dof,
                        eigenvalue_unit(scene, convention))
    return replace(band, convention=convention)
