"""The transverse (y) eigenmode of the chain and the backward-wave prediction.

Charan et al. identify, among the 3N eigenvectors of J, one that is a pure
y transverse wave (no x or theta projection, their Fig. 6), with frequency
omega ~ 0.235 and wavelength ~2 (in 2R), and predict the backward sliding
wave speed V2 = omega / k.  Here: the right eigenvector of M^-1 J with the
largest fraction of its norm on the y coordinates, its frequency
``sqrt(-lambda)``, its dominant wavelength along the ring (discrete Fourier
transform of the y components, period 2NR) and ``omega / k``; all in the
paper's units (length 2R, time sqrt(m 2R / kn)).
"""

from dataclasses import dataclass

import numpy as np

from fricstab.analysis.spectrum import decompose
from fricstab.errors import ParameterError
from fricstab.scenes.chain import check_chain, forces_and_jacobian, mass_vector, time_unit

__all__ = ["TransverseMode", "transverse_mode"]


@dataclass(frozen=True)
class TransverseMode:
    """The most transverse eigenmode, in the paper's units."""

    y_fraction: float     # |v_y|^2 / |v|^2 of the right eigenvector
    omega: float          # sqrt(-lambda) in paper time units
    wavelength: float     # in units of 2R
    speed: float          # omega / k, paper units (2R per time unit)
    vector: np.ndarray    # the right eigenvector, (N, dof) real (generalized coordinates)


def transverse_mode(scene, state):
    """The chain's transverse mode: the real eigenmode with the largest y fraction.

    Charan compare the backward sliding wave V2 with the phase speed of this
    mode (Sec. IV); at F_x = 0 its frequency is 0.235 in their units.

    Parameters
    ----------
    scene : ChainScene
    state : State
        An equilibrium of the chain.

    Returns
    -------
    TransverseMode
        ``y_fraction`` (``|v_y|^2 / |v|^2`` of the right eigenvector),
        ``omega`` (``sqrt(-lambda)`` in paper time units ``sqrt(m 2R/k_n)``),
        ``wavelength`` (units of 2R), ``speed`` (``omega / k``, 2R per paper
        time unit) and ``vector`` (N, dof).
    """
    check_chain(scene, state)
    _, jac = forces_and_jacobian(scene, state)
    spec = decompose(jac, mass_vector(scene))
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
    unit = time_unit(scene)
    omega = float(np.sqrt(-spec.eigenvalues[k].real)) * unit
    amp = np.abs(np.fft.rfft(v[:, 1]))
    amp[0] = 0.0  # a uniform y motion has no wavelength
    m = int(np.argmax(amp)) if amp.max() > 0 else 0
    ring = scene.period / length
    wavelength = ring / m if m else np.inf
    wavenumber = 2 * np.pi / wavelength
    return TransverseMode(best_frac, omega, float(wavelength), float(omega / wavenumber), v)
