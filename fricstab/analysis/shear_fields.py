"""Measures of a displacement field around a point: its angular modes and its concentration.

Used for Lee & Hurley's Fig. 7 (a quadrupolar non-affine displacement at a shear
transformation zone, :func:`fricstab.analysis.shear_event.stz_quadrupole`); plain arrays in,
positions periodic in x when a period ``lx`` is given.
"""

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["QUADRUPOLAR", "angular_modes", "concentration", "distance", "min_image",
           "periodic_centroid"]

#: m = 2 carries at least this share of the angular power: quadrupolar (Fig. 7).
QUADRUPOLAR = 0.5


def min_image(x, lx):
    """``x`` folded to the minimum image of period ``lx`` (None: not periodic)."""
    return x if lx is None else x - lx * np.round(x / lx)


def periodic_centroid(xy, lx):
    """Centroid of points (..., n, 2), the circular mean in x of period ``lx``."""
    ang = 2 * np.pi * xy[..., 0] / lx
    x = lx * np.arctan2(np.sin(ang).mean(-1), np.cos(ang).mean(-1)) / (2 * np.pi)
    return np.stack([x, xy[..., 1].mean(-1)], -1)


def distance(a, b, lx):
    """Distance of points ``a`` and ``b`` (broadcast), minimum image in x."""
    d = np.asarray(a, float) - np.asarray(b, float)
    return np.hypot(min_image(d[..., 0], lx), d[..., 1])


def angular_modes(pos, u, centre, lx=None, r_in=1.0, r_out=6.0, m_max=4):
    """Angular Fourier content of the radial component of a displacement field.

    Fits ``r u_r = a_0 + sum_m (a_m cos(m theta) + b_m sin(m theta))``, m = 1..``m_max``,
    by least squares over the points with ``r_in < r <= r_out`` from ``centre``; the factor
    r undoes the 1/r decay of an Eshelby far field, whose ``u_r`` is pure m = 2.  Power of
    m: ``a_0^2`` (m = 0), ``(a_m^2 + b_m^2) / 2``.  Quadrupolar when m = 2 has the largest
    share and at least :data:`QUADRUPOLAR`.  For an isotropic random field the m = 2 share
    is ~ Beta(1, 7/2) (2 of 9 Gaussian degrees of freedom), so a random field is called
    quadrupolar with probability 0.5^3.5 = 0.088.  No shares ("no radial motion") when
    the fitted power is below 1e-20 of the mean ``r^2 |u|^2`` (``u_r`` at rounding level).

    Parameters
    ----------
    pos, u : ndarray, shape (n, 2)
        Points and displacements (the length unit of ``lx``, ``r_in``, ``r_out``).
    centre : array_like, shape (2,)
    lx : float, optional
        Period in x (minimum image); None: not periodic.
    r_in, r_out : float
        The annulus.
    m_max : int
        Highest mode (>= 2).

    Returns
    -------
    dict
        ``n`` points, ``shares`` (m = 0..m_max, None when not computable), ``dominant``,
        ``quadrupolar``, ``axis`` (rad: the direction of the largest outward m = 2 motion,
        mod pi), ``status``.
    """
    if isinstance(m_max, bool) or not isinstance(m_max, (int, np.integer)) or m_max < 2:
        raise ParameterError(f"m_max = {m_max!r}: an integer >= 2")
    d = np.asarray(pos, float) - np.asarray(centre, float)
    d[:, 0] = min_image(d[:, 0], lx)
    r, u = np.hypot(d[:, 0], d[:, 1]), np.asarray(u, float)
    sel = (r > r_in) & (r <= r_out) & np.all(np.isfinite(u), 1)
    th, y = np.arctan2(d[sel, 1], d[sel, 0]), np.einsum("ij,ij->i", u[sel], d[sel])
    cols = [np.ones_like(th)] + [f(m * th) for m in range(1, m_max + 1) for f in (np.cos, np.sin)]
    out = {"n": int(sel.sum()), "shares": None, "dominant": None, "quadrupolar": None,
           "axis": None, "status": "ok"}
    if out["n"] < 2 * len(cols):
        out["status"] = f"too few points ({out['n']} < {2 * len(cols)})"
        return out
    c, _, rank, _ = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)
    power = np.array([c[0] ** 2] + [(c[2 * m - 1] ** 2 + c[2 * m] ** 2) / 2
                                    for m in range(1, m_max + 1)])
    scale = np.mean((u[sel] ** 2).sum(1) * r[sel] ** 2)     # all motion, radial or not
    if rank < len(cols) or not power.sum() > 1e-20 * scale:  # u_r at rounding level: none
        out["status"] = "angles do not cover the circle" if rank < len(cols) else \
            "no radial motion"
        return out
    shares = power / power.sum()
    out.update(shares=shares.tolist(), dominant=int(np.argmax(shares)),
               quadrupolar=bool(np.argmax(shares) == 2 and shares[2] >= QUADRUPOLAR),
               axis=float(np.arctan2(c[4], c[3]) / 2))
    return out


def concentration(pos, u, centre, radius, lx=None):
    """Enrichment of motion near ``centre``: the share of ``sum |u|^2`` within ``radius``
    over the share of the points within it.

    1 for a field without structure (relative spread ~ 1/sqrt(points inside)).

    Parameters
    ----------
    pos, u, centre, lx
        As :func:`angular_modes`.
    radius : float

    Returns
    -------
    float or None
        None when nothing moves or no point is inside.
    """
    u = np.asarray(u, float)
    ok = np.all(np.isfinite(u), 1)
    w = (u[ok] ** 2).sum(1)
    inside = distance(np.asarray(pos, float)[ok], centre, lx) <= radius
    if not inside.any() or not w.sum() > 0:
        return None
    return float(w[inside].sum() / w.sum() / inside.mean())
