"""The system Jacobian ``K = dF/dq`` with the history's increment rule, sparse.

Assembled from the contact blocks of :func:`fricstab.engine.passes.eval_pass`
(each the generated, verified block of one contact).  Rows and columns are
the degrees of freedom of the free particles (family 0), particle by
particle, ``dof`` each in the order ``(x, y[, r])``; fixed and driven
particles are clamped (their rows and columns dropped).  ``r`` is the law's
rotational coordinate (``theta``, or ``l = R theta`` for Ishima's law).

Sign: ``K = dF/dq`` (Charan's sign).  Ishima's Jacobian (Eq. 18) is ``-K``;
``M q'' = K q`` for small motions, so a stable mode has a negative
eigenvalue of ``M^-1 K``.
"""

import numpy as np
import scipy.sparse as sps

__all__ = ["assemble", "dof_index", "dof_labels", "jacobian"]

COORDINATE_NAMES = {"theta": ("x", "y", "theta"), "l": ("x", "y", "l"), "": ("x", "y")}


def dof_index(family, dof, free_only=True):
    """First dof of each particle in the Jacobian, -1 for a clamped particle."""
    free = np.asarray(family) == 0 if free_only else np.ones(len(family), bool)
    index = np.full(len(free), -1, np.int64)
    index[free] = dof * np.arange(int(free.sum()))
    return index


def assemble(contacts, blocks, family, dof, free_only=True):
    """``K`` (CSR) from per-contact blocks (K, 2 dof, 2 dof); clamped dof dropped.

    ``free_only=False`` keeps every particle's dof (fixed and driven ones too):
    the matrix whose null space holds the rigid translations of a periodic box.
    """
    index = dof_index(family, dof, free_only)
    n_dof = int((index >= 0).sum()) * dof
    if contacts.n == 0:
        return sps.csr_matrix((n_dof, n_dof))
    touching = np.any(blocks != 0.0, axis=(1, 2))
    ci, cj, b = contacts.i[touching], contacts.j[touching], blocks[touching]
    local = np.arange(dof)
    ii = index[ci]
    jj = np.where(cj >= 0, index[np.maximum(cj, 0)], -1)
    first = np.where(ii[:, None] >= 0, ii[:, None] + local, -1)
    second = np.where(jj[:, None] >= 0, jj[:, None] + local, -1)
    dofs = np.concatenate([first, second], axis=1)
    rows = np.repeat(dofs[:, :, None], 2 * dof, axis=2)
    cols = np.repeat(dofs[:, None, :], 2 * dof, axis=1)
    keep = (rows >= 0) & (cols >= 0)
    return sps.csr_matrix((b[keep], (rows[keep], cols[keep])), shape=(n_dof, n_dof))


def jacobian(system, state, free_only=True):
    """Generalized forces and the sparse Jacobian ``K = dF/dq`` with history.

    Assembled from the verified per-contact blocks of the law: the history is
    advanced by the increment rule (Charan Eq. 2, Ishima Eq. D4) and the
    derivative through the Coulomb threshold is included.  Charan's sign
    (Ishima's Jacobian, Eq. 18, is ``-K``).

    Parameters
    ----------
    system : System
    state : State
    free_only : bool
        True: the rows and columns of the free particles' dof only (fixed and
        driven particles clamped); False: every particle's dof.

    Returns
    -------
    f : ndarray, shape (n_dof,)
        Generalized forces of those dof, particle by particle (force; torque or
        T/R for the rotation coordinate).
    K : scipy.sparse.csr_matrix, shape (n_dof, n_dof)
        ``K[a, b] = d f[a] / d q[b]`` (force/length; dof order x, y, rotation
        per particle).
    """
    f, blocks = system.forces(state, want_blocks=True)
    k = assemble(state.contacts, blocks, system.family, system.dof, free_only)
    keep = system.family == 0 if free_only else np.ones(system.n, bool)
    return f[keep, :system.dof].ravel(), k


def dof_labels(system):
    """``[particle, coordinate name]`` per row and column of the Jacobian."""
    names = COORDINATE_NAMES[system.material.rotation][:system.dof]
    return [[int(i), c] for i in np.flatnonzero(system.family == 0) for c in names]
