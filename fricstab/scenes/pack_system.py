"""Contact network, forces and the sparse Jacobian of a periodic disk packing.

Convention: Ishima et al. (2023).  Coordinates per particle
``q_i = (x_i, y_i, l_i)`` with ``l_i = d_i theta_i / 2``; generalized force
``(F_x, F_y, F^l = 2 T / d)``; the Jacobian is ``J = -dF/dq`` (Eq. 18), with
the tangential history advanced by the increment rule (Eq. D4), assembled
from the verified generated kernels (``fricstab.generated.ishima``: blocks
``K = dF/dq``, so ``J = -K``).  "Model only what a scene requires": with
``kt = 0`` the packing is frictionless, the coordinates are ``(x_i, y_i)``
and ``J`` is the Hessian of the Hertz potential (``fricstab.generated.hertz``).

Units: large diameter ``d = 1``, ``k_N = 1``, mass of a large disk ``m = 1``;
so ``t0 = 1``, forces in ``k_N d^(3/2)``, stiffness and ``J`` in ``k_N d^(1/2)``.

Periodic box of side ``L`` with a Lees-Edwards offset ``shift = gamma L``:
``sep[c] = r_i - r_j`` of the minimum image (:func:`fricstab.scenes.packing.find_contacts`).
Histories ``hist`` (M, 2) belong to the contacts ``pairs`` (M, 2), i < j.
"""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps

from fricstab._numba import kernel_jit
from fricstab.generated.hertz import hertz_assemble, hertz_force
from fricstab.generated.ishima import ishima_assemble, ishima_force, ishima_increment
from fricstab.laws import ParameterError
from fricstab.scenes.packing import find_contacts

__all__ = ["Backbone", "Network", "affine_rates", "assemble", "backbone", "carry_history",
           "network", "rattler_mask", "shear_stress", "sparse_jacobian"]

KN = 1.0  # the unit of stiffness


def _check_kt(kt):
    if not (np.isfinite(kt) and kt >= 0):
        raise ParameterError(f"kt (= kT/kN) must be a finite number >= 0, got {kt!r}")
    return float(kt)


def ndof(kt):
    """Coordinates per particle: 3 with friction, 2 without (``kt == 0``).

    Raises ParameterError unless ``kt`` (= kT/kN) is finite and >= 0.
    """
    return 3 if _check_kt(kt) > 0 else 2


@dataclass(frozen=True)
class Network:
    """Contacts of a configuration: ``pairs`` (M, 2), ``sep`` (M, 2), ``hist`` (M, 2)."""

    pairs: np.ndarray
    sep: np.ndarray
    hist: np.ndarray

    @property
    def m(self):
        return len(self.pairs)


def network(pos, radius, box, shift=0.0, previous=None):
    """Contacts of ``pos``; histories carried over from ``previous`` (new ones zero)."""
    pairs, sep = find_contacts(pos, radius, box, shift)
    hist = np.zeros((len(pairs), 2))
    if previous is not None and previous.m:
        hist = carry_history(previous.pairs, previous.hist, pairs, len(radius))
    return Network(pairs, sep, hist)


def carry_history(old_pairs, old_hist, new_pairs, n):
    """Histories of ``new_pairs``: that of the same pair in ``old_pairs``, else zero."""
    hist = np.zeros((len(new_pairs), 2))
    if len(old_pairs) == 0 or len(new_pairs) == 0:
        return hist
    old_key = old_pairs[:, 0] * n + old_pairs[:, 1]
    new_key = new_pairs[:, 0] * n + new_pairs[:, 1]
    order = np.argsort(old_key)
    pos = np.searchsorted(old_key[order], new_key)
    pos = np.minimum(pos, len(old_key) - 1)
    found = old_key[order][pos] == new_key
    hist[found] = old_hist[order][pos[found]]
    return hist


def assemble(net, radius, kt):
    """Generalized forces (N, ndof) and contact blocks ``K_c = dF/dq`` (M, 2 ndof, 2 ndof)."""
    n, k = len(radius), ndof(kt)
    forces = np.zeros((n, k))
    blocks = np.zeros((net.m, 2 * k, 2 * k))
    if net.m:
        if kt > 0:
            ishima_assemble(net.sep, radius, net.pairs, KN, kt, net.hist, forces, blocks)
        else:
            hertz_assemble(net.sep, radius, net.pairs, KN, forces, blocks)
    return forces, blocks


def contact_dofs(pairs, k):
    """Global coordinate indices of each contact's 2k block rows/columns."""
    local = np.arange(k)
    return np.concatenate([pairs[:, :1] * k + local, pairs[:, 1:] * k + local], axis=1)


def sparse_jacobian(pairs, blocks, n, kt):
    """``J = -dF/dq`` (Ishima Eq. 18) as CSR, ordering (x, y, l) per particle."""
    k = ndof(kt)
    dofs = contact_dofs(pairs, k)
    rows = np.repeat(dofs[:, :, None], 2 * k, axis=2).ravel()
    cols = np.repeat(dofs[:, None, :], 2 * k, axis=1).ravel()
    return sps.csr_matrix((-blocks.ravel(), (rows, cols)), shape=(n * k, n * k))


@kernel_jit
def _ishima_x_rates(sep, radius, pairs, kn, kt, hist, h, out):
    f = np.empty(6, dtype=np.complex128)
    for c in range(pairs.shape[0]):
        ishima_force(complex(sep[c, 0], h), complex(sep[c, 1], 0.0), complex(radius[pairs[c, 0]]),
                     complex(radius[pairs[c, 1]]), complex(kn), complex(kt),
                     complex(hist[c, 0]), complex(hist[c, 1]), f)
        for a in range(6):
            out[c, a] = f[a].imag / h


@kernel_jit
def _hertz_x_rates(sep, radius, pairs, kn, h, out):
    f = np.empty(4, dtype=np.complex128)
    for c in range(pairs.shape[0]):
        hertz_force(complex(sep[c, 0], h), complex(sep[c, 1], 0.0), complex(radius[pairs[c, 0]]),
                    complex(radius[pairs[c, 1]]), complex(kn), f)
        for a in range(4):
            out[c, a] = f[a].imag / h


def affine_rates(net, radius, kt):
    """``dF_c / d(dx)`` at frozen history, per contact (M, 2 ndof).

    An affine step strain moves ``dx`` of a contact by ``dgamma * sep_y`` and
    leaves its history unchanged (the step is instantaneous: Ishima Sec. III B);
    so the affine force rate of contact c is this row times ``sep_y``.  Complex
    step through the verified force kernel: exact to round-off.
    """
    k = ndof(kt)
    out = np.zeros((net.m, 2 * k))
    if net.m:
        h = 1e-30
        if kt > 0:
            _ishima_x_rates(net.sep, radius, net.pairs, KN, kt, net.hist, h, out)
        else:
            _hertz_x_rates(net.sep, radius, net.pairs, KN, h, out)
    return out


def contact_forces(net, radius, kt):
    """Force on particle i from j, ``f_c`` (M, 2), from the verified force kernel."""
    forces = np.zeros((net.m, 2))
    one = np.zeros(2 * ndof(kt))
    for c in range(net.m):  # a Python loop over contacts: used on final states only
        i, j = net.pairs[c]
        if kt > 0:
            ishima_force(net.sep[c, 0], net.sep[c, 1], radius[i], radius[j], KN, kt,
                         net.hist[c, 0], net.hist[c, 1], one)
        else:
            hertz_force(net.sep[c, 0], net.sep[c, 1], radius[i], radius[j], KN, one)
        forces[c] = one[:2]
    return forces


def shear_stress(net, radius, kt, box):
    """``sigma_xy = -(1/L^2) sum_c f_c^x y_c`` (Ishima Eq. 14), sum over contacts."""
    f = contact_forces(net, radius, kt)
    terms = f[:, 0] * net.sep[:, 1]
    return -terms.sum() / box**2, np.abs(terms).sum() / box**2


def history_increment(net, radius, dq, k):
    """``dt_c = A_c dq_c`` (Ishima Eq. D4) at the configuration of ``net``."""
    a = np.zeros((2, 6))
    dofs = contact_dofs(net.pairs, k)
    out = np.zeros((net.m, 2))
    for c in range(net.m):
        ishima_increment(net.sep[c, 0], net.sep[c, 1], radius[net.pairs[c, 0]],
                         radius[net.pairs[c, 1]], a)
        out[c] = a @ dq[dofs[c]]
    return out


def rattler_mask(pairs, n, z_th=2):
    """Rattlers by iterative removal (Ishima App. E.1): Z_i <= z_th, repeated."""
    rattler = np.zeros(n, dtype=bool)
    while True:
        live = ~(rattler[pairs[:, 0]] | rattler[pairs[:, 1]])
        z = np.bincount(pairs[live].ravel(), minlength=n)
        new = (z <= z_th) & ~rattler
        if not new.any():
            return rattler
        rattler |= new


@dataclass(frozen=True)
class Backbone:
    """The packing without rattlers: what the rigidity and the DOS are about."""

    pos: np.ndarray
    radius: np.ndarray
    box: float
    keep: np.ndarray       # indices of the kept particles in the packing
    n_total: int           # particles of the packing, rattlers included
    rattler_force: float   # largest |f| of a removed contact (0 if rattlers are free)

    @property
    def n(self):
        return len(self.radius)


def backbone(packing, z_th=2, f_tol=1e-14):
    """Remove rattlers (and their contacts) from ``packing``.

    A removed contact that carried force (a rattler held between two
    diametrically opposite neighbours) leaves the backbone out of balance; it
    is then relaxed frictionlessly (Newton) to ``max |F| < f_tol``, so that
    theory and simulation start from the same force-balanced state.
    """
    radius = packing.diameter / 2
    net = network(packing.pos, radius, packing.box)
    rattler = rattler_mask(net.pairs, len(radius), z_th)
    removed = rattler[net.pairs[:, 0]] | rattler[net.pairs[:, 1]]
    f = contact_forces(Network(net.pairs[removed], net.sep[removed], net.hist[removed]),
                       radius, 0.0) if removed.any() else np.zeros((0, 2))
    keep = np.flatnonzero(~rattler)
    if len(keep) < 2:
        raise ParameterError(f"the packing (N = {len(radius)}, phi = {packing.phi:g}) has no "
                             f"rigid backbone: every particle is a rattler (Z <= {z_th})")
    pos = packing.pos[keep].copy()
    net_b = network(pos, radius[keep], packing.box)
    forces, _ = assemble(net_b, radius[keep], 0.0)
    if np.abs(forces).max() >= f_tol:
        from fricstab.protocols.stepstrain import relax
        pos = relax(pos, np.zeros(len(keep)), radius[keep], packing.box, 0.0,
                    f_tol=f_tol).pos
    return Backbone(pos, radius[keep].copy(), float(packing.box), keep,
                    len(radius), float(np.abs(f).max()) if len(f) else 0.0)
