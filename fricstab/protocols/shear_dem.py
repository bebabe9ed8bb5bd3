"""The numba loop of the plane-shear DEM: neighbour list, contact forces, velocity Verlet.

Everything here works in the reduced units of :mod:`fricstab.scenes.shear` (length:
mean radius; pressure: E*; mass per unit thickness: rho x length^2); the
kernels of the contact law are unit-agnostic.

Arrays (n particles, m pairs of the neighbour list)
---------------------------------------------------
``pos (n, 2)`` x *unwrapped* (never folded into the box: the minimum image
``d - lx round(d / lx)`` is taken per pair), ``vel (n, 2)``, ``angle (n,)``,
``omega (n,)`` counter-clockwise positive; ``force (n, 2)``, ``torque (n,)``
the contact forces of the last evaluation; ``radius, mass, inertia (n,)``;
``kind (n,)`` int8: 0 bulk, 1 bottom wall (fixed), 2 top wall (rigid);
``mdamp, idamp (n,)`` the masses and inertias that enter the damping
coefficients (bulk: own; bottom wall: inf; top wall: the wall's total mass,
inertia inf, because a wall disk moves with the whole wall and never rotates).

Pairs ``pi < pj`` (int64, sorted by the key ``pi n + pj``) are every pair
with a gap below ``skin`` except wall-wall pairs.  Per pair, state: ``ft``
(capped elastic tangential force, along t = (-n_y, n_x)), ``mr`` (capped
rolling spring torque), ``kt, kr`` of the last step (for the next increment);
output of the last force evaluation: ``cf (m, 2)`` total force on i from j,
``cfn`` elastic normal force, ``csl`` sliding flag (0 none, 1 tangential,
2 rolling, 3 both).  A pair that separates loses its history.

Contact law: :func:`fricstab.generated.lee_hurley.lee_hurley_contact`
(elastic parts, A1-A3, A7-A10, A14-A18, A23 with the caps) plus the linear
damping of :func:`fricstab.protocols.shear_law.damping_coefficients` (A4, A11, A12,
A19-A22) as in /tmp/me/contract_lee_hurley.md: F_i = (Fn - gamma_n v_n) n -
(ft_c + gamma_t v_t) t, T_i = R_i (ft_c + gamma_t v_t) + mr_c + M_d,
T_j = R_j (ft_c + gamma_t v_t) - mr_c - M_d, M_d = -C_r (w_i - w_j) unless
the rolling spring slides.  Increments (contract): d ft = k_t v_t dt with
v_t = t.(v_i - v_j) - (R_i w_i + R_j w_j); d mr = -k_r (w_i - w_j) dt, with the
k_t, k_r of the previous step (a new contact has none: its first increment
is zero, an O(dt) start-up error).

Integrator: velocity Verlet, half kick - drift - force - half kick, with the
forces evaluated at the half-step velocities (the damping and the increments
use the velocities of the drift, so d delta_t is the exact relative
tangential displacement of the drift).  The top wall moves at (V, v_y) with
the servo v_y = -gain (N_target - N) clipped to |v_y| <= vmax, N the sum of
the y forces on the top-wall disks of the previous step (LIGGGHTS-style
velocity servo).

Status codes returned by :func:`run_steps`: 0 ok; 1 overlap beyond the
domain of the contact law at pair ``item``; 2 non-finite position or
velocity of particle ``item``; 3 non-finite contact force at pair ``item``.
"""

import numpy as np

from fricstab._numba import kernel_jit
from fricstab.generated.lee_hurley import lee_hurley_contact
from fricstab.protocols.shear_law import damping_coefficients

__all__ = ["build_pairs", "carry_histories", "compute_forces", "run_steps", "OK",
           "BAD_OVERLAP", "BAD_STATE", "BAD_FORCE"]

OK, BAD_OVERLAP, BAD_STATE, BAD_FORCE = 0, 1, 2, 3
_E2 = np.exp(2.0)


@kernel_jit
def build_pairs(pos, radius, kind, lx, skin):
    """Pairs (i < j, sorted by i n + j) with gap < ``skin``; no wall-wall pairs.

    A cell list periodic in x (cell size >= 2 max radius + skin), open in y.
    Returns ``(pi, pj)`` int64 arrays; the result depends only on the inputs.
    """
    n = pos.shape[0]
    rmax = radius.max()
    cs = 2.0 * rmax + skin
    ncx = int(np.floor(lx / cs))
    if ncx < 3:
        ncx = 1
    ymin = pos[:, 1].min()
    ymax = pos[:, 1].max()
    ncy = int(np.floor((ymax - ymin) / cs)) + 1
    cx = np.empty(n, np.int64)
    cy = np.empty(n, np.int64)
    for i in range(n):
        xw = pos[i, 0] - lx * np.floor(pos[i, 0] / lx)
        c = int(xw / lx * ncx)
        cx[i] = min(max(c, 0), ncx - 1)
        cy[i] = min(int((pos[i, 1] - ymin) / cs), ncy - 1)
    ncell = ncx * ncy
    head = -np.ones(ncell, np.int64)
    nxt = -np.ones(n, np.int64)
    for i in range(n - 1, -1, -1):
        c = cy[i] * ncx + cx[i]
        nxt[i] = head[c]
        head[c] = i
    cap = 8 * n + 16
    keys = np.empty(cap, np.int64)
    m = 0
    rx = 1 if ncx >= 3 else 0
    for i in range(n):
        for oy in range(-1, 2):
            yy = cy[i] + oy
            if yy < 0 or yy >= ncy:
                continue
            for ox in range(-rx, rx + 1):
                xx = (cx[i] + ox) % ncx
                j = head[yy * ncx + xx]
                while j >= 0:
                    if j > i and not (kind[i] != 0 and kind[j] != 0):
                        dx = pos[i, 0] - pos[j, 0]
                        dx -= lx * np.round(dx / lx)
                        dy = pos[i, 1] - pos[j, 1]
                        cut = radius[i] + radius[j] + skin
                        if dx * dx + dy * dy < cut * cut:
                            if m == cap:
                                grown = np.empty(2 * cap, np.int64)
                                grown[:m] = keys[:m]
                                keys = grown
                                cap *= 2
                            keys[m] = i * n + j
                            m += 1
                    j = nxt[j]
    keys = np.sort(keys[:m])
    # a box of fewer than 3 cells in x visits a cell twice: drop duplicates
    k = 0
    for a in range(m):
        if a == 0 or keys[a] != keys[a - 1]:
            keys[k] = keys[a]
            k += 1
    pi = keys[:k] // n
    pj = keys[:k] % n
    return pi, pj


@kernel_jit
def carry_histories(n, old_i, old_j, old_h, new_i, new_j):
    """Histories of the new pair list: rows of ``old_h (m_old, k)`` by pair key, else 0."""
    m = new_i.shape[0]
    out = np.zeros((m, old_h.shape[1]))
    a = 0
    mo = old_i.shape[0]
    for b in range(m):
        key = new_i[b] * n + new_j[b]
        while a < mo and old_i[a] * n + old_j[a] < key:
            a += 1
        if a < mo and old_i[a] * n + old_j[a] == key:
            out[b, :] = old_h[a, :]
    return out


@kernel_jit
def compute_forces(pos, vel, omega, radius, mdamp, idamp, kind, lx, pi, pj, hist, cf, cfn,
                   csl, law, dt, force, torque):
    """Contact forces and torques at ``pos`` with the half-step velocities; updates ``hist``.

    ``hist (m, 4)`` = (ft, mr, kt, kr) per pair; ``law`` = (E*, nu, mu_s, mu_r,
    alpha_n, alpha_t, eta_r).  Returns ``(status, item, Fx_top, Fy_top)``: the
    summed contact force on the top-wall disks.
    """
    n = pos.shape[0]
    for i in range(n):
        force[i, 0] = 0.0
        force[i, 1] = 0.0
        torque[i] = 0.0
    E, nu, mus, mur, an, at, er = law[0], law[1], law[2], law[3], law[4], law[5], law[6]
    out = np.empty(9)
    fxw = 0.0
    fyw = 0.0
    for k in range(pi.shape[0]):
        i = pi[k]
        j = pj[k]
        dx = pos[i, 0] - pos[j, 0]
        dx -= lx * np.round(dx / lx)
        dy = pos[i, 1] - pos[j, 1]
        ri = radius[i]
        rj = radius[j]
        r2 = dx * dx + dy * dy
        s = ri + rj
        if r2 >= s * s:
            hist[k, 0] = 0.0
            hist[k, 1] = 0.0
            hist[k, 2] = 0.0
            hist[k, 3] = 0.0
            cf[k, 0] = 0.0
            cf[k, 1] = 0.0
            cfn[k] = 0.0
            csl[k] = 0
            continue
        r = np.sqrt(r2)
        if s - r >= 0.999 * 4.0 * s / _E2:
            return BAD_OVERLAP, k, fxw, fyw
        nx = dx / r
        ny = dy / r
        tx = -ny
        ty = nx
        vx = vel[i, 0] - vel[j, 0]
        vy = vel[i, 1] - vel[j, 1]
        vn = vx * nx + vy * ny
        vt = vx * tx + vy * ty - (ri * omega[i] + rj * omega[j])
        wr = omega[i] - omega[j]
        ft = hist[k, 0] + hist[k, 2] * vt * dt
        mr = hist[k, 1] - hist[k, 3] * wr * dt
        lee_hurley_contact(dx, dy, ri, rj, E, nu, mus, mur, ft, mr, out)
        kn, kt, kr, fn, ftc, mrc = out[2], out[3], out[4], out[5], out[6], out[7]
        flag = int(out[8])
        gn, gt, cr = damping_coefficients(kn, kt, kr, mdamp[i], mdamp[j], idamp[i], idamp[j],
                                          ri, rj, an, at, er)
        fnt = fn - gn * vn
        ftt = ftc + gt * vt
        md = 0.0 if (flag & 2) else -cr * wr
        fx = fnt * nx - ftt * tx
        fy = fnt * ny - ftt * ty
        if not (abs(fx) < np.inf and abs(fy) < np.inf and abs(md) < np.inf):
            return BAD_FORCE, k, fxw, fyw
        force[i, 0] += fx
        force[i, 1] += fy
        force[j, 0] -= fx
        force[j, 1] -= fy
        torque[i] += ri * ftt + mrc + md
        torque[j] += rj * ftt - mrc - md
        if kind[i] == 2:
            fxw += fx
            fyw += fy
        if kind[j] == 2:
            fxw -= fx
            fyw -= fy
        hist[k, 0] = ftc
        hist[k, 1] = mrc
        hist[k, 2] = kt
        hist[k, 3] = kr
        cf[k, 0] = fx
        cf[k, 1] = fy
        cfn[k] = fn
        csl[k] = flag
    return OK, -1, fxw, fyw


@kernel_jit
def run_steps(nsteps, pos, vel, angle, omega, force, torque, radius, mass, inertia, mdamp,
              idamp, kind, lx, pi, pj, hist, ref, cf, cfn, csl, law, dt, skin, wall, ctrl):
    """Advance ``nsteps`` velocity-Verlet steps (arrays updated in place).

    ``wall`` (float64, 8): (x offset of the top wall since the start, N
    measured, S measured, y velocity, y of the bottom reference, unused x3);
    ``ctrl`` (8): (V, N_target, gain, vmax, global damping rate c (prep: bulk
    velocities scaled by 1 - c dt), affine compression flag, unused x2).
    ``ref (n, 2)``: positions at the last neighbour-list build; the list is
    rebuilt (histories carried by pair key) when a particle moved more than
    skin / 2 since.  Returns ``(status, step, item, pi, pj, hist, cf, cfn,
    csl, rebuilds)`` with the possibly new pair arrays.
    """
    n = pos.shape[0]
    V, ntarget, gain, vmax, cdamp, affine = ctrl[0], ctrl[1], ctrl[2], ctrl[3], ctrl[4], ctrl[5]
    half = 0.5 * dt
    rebuilds = 0
    ytop = 0.0
    nt = 0
    for i in range(n):
        if kind[i] == 2:
            ytop += pos[i, 1]
            nt += 1
    ytop /= max(nt, 1)
    for step in range(nsteps):
        vy = -gain * (ntarget - wall[1])
        if vy > vmax:
            vy = vmax
        elif vy < -vmax:
            vy = -vmax
        wall[3] = vy
        h = ytop - wall[4]
        scale = 1.0 + vy * dt / h if affine > 0.0 else 1.0
        damp = 1.0 - cdamp * dt
        maxd2 = 0.0
        for i in range(n):
            if kind[i] == 0:
                vel[i, 0] += half * force[i, 0] / mass[i]
                vel[i, 1] += half * force[i, 1] / mass[i]
                omega[i] += half * torque[i] / inertia[i]
                if cdamp > 0.0:
                    vel[i, 0] *= damp
                    vel[i, 1] *= damp
                    omega[i] *= damp
                pos[i, 0] += vel[i, 0] * dt
                pos[i, 1] += vel[i, 1] * dt
                if affine > 0.0:
                    pos[i, 1] = wall[4] + (pos[i, 1] - wall[4]) * scale
                angle[i] += omega[i] * dt
            elif kind[i] == 2:
                vel[i, 0] = V
                vel[i, 1] = vy
                pos[i, 0] += V * dt
                pos[i, 1] += vy * dt
            ex = pos[i, 0] - ref[i, 0]
            ey = pos[i, 1] - ref[i, 1]
            d2 = ex * ex + ey * ey
            if not (d2 < np.inf):
                return BAD_STATE, step, i, pi, pj, hist, cf, cfn, csl, rebuilds
            if d2 > maxd2:
                maxd2 = d2
        ytop += vy * dt
        wall[0] += V * dt
        if maxd2 > 0.25 * skin * skin:
            ni, nj = build_pairs(pos, radius, kind, lx, skin)
            hist = carry_histories(n, pi, pj, hist, ni, nj)
            pi, pj = ni, nj
            cf = np.zeros((pi.shape[0], 2))
            cfn = np.zeros(pi.shape[0])
            csl = np.zeros(pi.shape[0], np.int8)
            ref[:, :] = pos
            rebuilds += 1
        status, item, fxw, fyw = compute_forces(pos, vel, omega, radius, mdamp, idamp, kind,
                                                lx, pi, pj, hist, cf, cfn, csl, law, dt,
                                                force, torque)
        if status != OK:
            return status, step, item, pi, pj, hist, cf, cfn, csl, rebuilds
        wall[1] = fyw
        wall[2] = -fxw
        for i in range(n):
            if kind[i] == 0:
                vel[i, 0] += half * force[i, 0] / mass[i]
                vel[i, 1] += half * force[i, 1] / mass[i]
                omega[i] += half * torque[i] / inertia[i]
    return OK, nsteps, -1, pi, pj, hist, cf, cfn, csl, rebuilds
