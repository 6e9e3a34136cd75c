#!/usr/bin/env python3
"""An independent finite-element reference for the bilinear Taylor bar.

The computational Taylor bar of docs/method.md §12 (copper rod 32.4 mm long,
3.2 mm in radius, 227 m/s onto a rigid frictionless wall, E 117 GPa,
nu 0.35, J2 plasticity with linear hardening from 400 MPa, tangent modulus
100 MPa) on a structured mesh of four-node quadrilaterals: one-point
integration with Flanagan-Belytschko viscous hourglass control, a bulk
viscosity in compression, Jaumann-rate hypoelasticity with radial return,
lumped masses and central differences. The wall is a unilateral kinematic
constraint: a face node that reaches it stops there, and one that the rod
pulls away leaves it freely, so the history of the node on the axis at the
impact face shows whether and when the face's centre separates.

It checks the SPH solver against a method that shares none of its code;
it is not part of the test suite (it needs numpy). Run, for example:

    python3 scripts/taylor_fe.py --across 16 --end 12e-6
    python3 scripts/taylor_fe.py --across 20 --end 80e-6
    python3 scripts/taylor_fe.py --across 16 --plane --end 12e-6

It prints each episode of the face centre moving up at more than 10 m/s
(when, how fast, how far off the wall), when it is off the wall, and the
rod's length, its largest radius and the plastic strain of the element at
the face's centre at the end.
"""
import argparse

import numpy as np

RADIUS, LENGTH, SPEED = 3.2e-3, 32.4e-3, 227.0
YOUNG, POISSON, DENSITY = 117e9, 0.35, 8930.0
YIELD, TANGENT = 0.4e9, 0.1e9


def run(across, axisymmetric=True, plastic=True, end=12e-6, held=False,
        hourglass=0.1, q_quad=1.5, q_lin=0.06, cfl=0.3):
    """Integrate to `end`; returns rows of (t, z and v_z of the face's axis
    node, rod length, largest radius, plastic strain of the element at the
    axis and the face)."""
    along = int(round(across * LENGTH / RADIUS))
    plastic_modulus = YOUNG * TANGENT / (YOUNG - TANGENT)
    bulk = YOUNG / (3 * (1 - 2 * POISSON))
    shear = YOUNG / (2 * (1 + POISSON))
    c_l = np.sqrt((bulk + 4 * shear / 3) / DENSITY)

    r1, z1 = np.linspace(0, RADIUS, across + 1), np.linspace(0, LENGTH, along + 1)
    rg, zg = np.meshgrid(r1, z1, indexing="ij")
    x = np.stack([rg.ravel(), zg.ravel()], 1)
    node = lambda i, j: i * (along + 1) + j  # noqa: E731
    conn = np.array([[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
                     for i in range(across) for j in range(along)])
    n_el = len(conn)
    v = np.zeros_like(x)
    v[:, 1] = -SPEED
    # Stress (rr, zz, θθ, rz), tension positive; equivalent plastic strain.
    sig = np.zeros((n_el, 4))
    eps_p = np.zeros(n_el)
    hg_vector = np.array([1.0, -1.0, 1.0, -1.0])

    def geometry(x):
        ex, ey = x[conn, 0], x[conn, 1]
        area = 0.5 * ((ex[:, 2] - ex[:, 0]) * (ey[:, 3] - ey[:, 1])
                      + (ex[:, 1] - ex[:, 3]) * (ey[:, 2] - ey[:, 0]))
        # Shape-function gradients at the centre (Flanagan & Belytschko 1981).
        bx = np.stack([ey[:, 1] - ey[:, 3], ey[:, 2] - ey[:, 0],
                       ey[:, 3] - ey[:, 1], ey[:, 0] - ey[:, 2]], 1) / (2 * area[:, None])
        by = np.stack([ex[:, 3] - ex[:, 1], ex[:, 0] - ex[:, 2],
                       ex[:, 1] - ex[:, 3], ex[:, 2] - ex[:, 0]], 1) / (2 * area[:, None])
        rc = ex.mean(1) if axisymmetric else np.ones(n_el)
        return ex, ey, area, bx, by, rc

    _, _, area0, _, _, rc0 = geometry(x)
    m_el = DENSITY * area0 * rc0
    mass = np.zeros(len(x))
    np.add.at(mass, conn.ravel(), np.repeat(m_el / 4, 4))
    on_axis = x[:, 0] < 1e-12
    centre = node(0, 0)
    on_wall = x[:, 1] <= 1e-14
    t, step, rows = 0.0, 0, []
    while t < end:
        ex, ey, area, bx, by, rc = geometry(x)
        if np.any(area <= 0):
            raise RuntimeError(f"an element inverted at {t:.3e} s")
        rho = m_el / (area * rc)
        d1 = np.hypot(ex[:, 2] - ex[:, 0], ey[:, 2] - ey[:, 0])
        d2 = np.hypot(ex[:, 3] - ex[:, 1], ey[:, 3] - ey[:, 1])
        dt = cfl * np.sqrt(2) * (area / np.maximum(d1, d2)).min() / c_l
        ve = v[conn]
        drr = (ve[:, :, 0] * bx).sum(1)
        dvr_dz = (ve[:, :, 0] * by).sum(1)
        dvz_dr = (ve[:, :, 1] * bx).sum(1)
        dzz = (ve[:, :, 1] * by).sum(1)
        dtt = ve[:, :, 0].mean(1) / rc if axisymmetric else np.zeros(n_el)
        drz, spin = 0.5 * (dvr_dz + dvz_dr), 0.5 * (dvr_dz - dvz_dr)
        div = drr + dzz + dtt

        p = -sig[:, :3].sum(1) / 3
        s = sig[:, :3] + p[:, None]
        srz = sig[:, 3].copy()
        srr, szz = s[:, 0].copy(), s[:, 1].copy()
        s[:, 0] += dt * 2 * spin * srz
        s[:, 1] -= dt * 2 * spin * srz
        srz += dt * spin * (szz - srr)
        s[:, 0] += dt * 2 * shear * (drr - div / 3)
        s[:, 1] += dt * 2 * shear * (dzz - div / 3)
        s[:, 2] += dt * 2 * shear * (dtt - div / 3)
        srz += dt * 2 * shear * drz
        p -= bulk * div * dt
        if plastic:
            seq = np.sqrt(1.5 * (s[:, 0] ** 2 + s[:, 1] ** 2 + s[:, 2] ** 2 + 2 * srz ** 2))
            flow = YIELD + plastic_modulus * eps_p
            over = seq > flow
            dep = np.where(over, (seq - flow) / (3 * shear + plastic_modulus), 0.0)
            scale = np.where(over, (flow + plastic_modulus * dep) / np.maximum(seq, 1e-30), 1.0)
            s *= scale[:, None]
            srz *= scale
            eps_p += dep
        sig[:, :3] = s - p[:, None]
        sig[:, 3] = srz

        size = np.sqrt(area)
        q = np.where(div < 0, rho * size * (q_quad * size * div ** 2 - q_lin * c_l * div), 0.0)
        s_rr, s_zz, s_tt = sig[:, 0] - q, sig[:, 1] - q, sig[:, 2] - q
        vol = area * rc
        fr = -(s_rr[:, None] * bx + sig[:, 3][:, None] * by) * vol[:, None]
        if axisymmetric:
            # ∫ σ_θθ N_a / r · r dA with one point: σ_θθ A / 4 at each node.
            fr -= (s_tt * 0.25 * area)[:, None]
        fz = -(sig[:, 3][:, None] * bx + s_zz[:, None] * by) * vol[:, None]
        gamma = (hg_vector[None, :] - (hg_vector[None, :] * ex).sum(1)[:, None] * bx
                 - (hg_vector[None, :] * ey).sum(1)[:, None] * by)
        qr, qz = (gamma * ve[:, :, 0]).sum(1), (gamma * ve[:, :, 1]).sum(1)
        ch = hourglass * rho * c_l * size * rc * 0.25
        fr -= (ch * qr)[:, None] * gamma
        fz -= (ch * qz)[:, None] * gamma
        f = np.zeros_like(x)
        np.add.at(f[:, 0], conn.ravel(), fr.ravel())
        np.add.at(f[:, 1], conn.ravel(), fz.ravel())

        v = v + dt * f / mass[:, None]
        v[on_axis, 0] = 0.0
        if held:
            v[on_wall, 1] = 0.0
        else:
            v[on_wall & (v[:, 1] < 0), 1] = 0.0
        x = x + dt * v
        through = x[:, 1] < 0
        x[through, 1] = 0.0
        v[through, 1] = 0.0
        on_wall = (on_wall | through) if held else x[:, 1] <= 1e-14
        t += dt
        step += 1
        if step % 5 == 0:
            rows.append((t, x[centre, 1], v[centre, 1], x[:, 1].max() - x[:, 1].min(), x[:, 0].max(),
                         eps_p[0]))
    return np.array(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--across", type=int, default=16, help="elements across the radius")
    ap.add_argument("--end", type=float, default=12e-6, help="end time, s")
    ap.add_argument("--plane", action="store_true", help="plane strain instead of axisymmetric")
    ap.add_argument("--elastic", action="store_true", help="no plasticity")
    ap.add_argument("--held", action="store_true", help="face nodes held at the wall once there")
    a = ap.parse_args()
    h = run(a.across, axisymmetric=not a.plane, plastic=not a.elastic, end=a.end, held=a.held)
    t, z, vz = h[:, 0] * 1e6, h[:, 1] * 1e3, h[:, 2]
    # Episodes of the face centre moving up at more than 10 m/s.
    up = vz > 10.0
    starts = np.nonzero(up & ~np.roll(up, 1))[0]
    for k0 in starts:
        k1 = k0 + np.argmin(up[k0:]) if not up[k0:].all() else len(up)
        k = k0 + np.argmax(vz[k0:k1])
        print(f"face centre moves up {t[k0]:.2f}-{t[k1 - 1]:.2f} us: at most {vz[k]:.1f} m/s"
              f" (at {t[k]:.2f} us), {z[k0:k1].max():.4f} mm off the wall")
    off = np.nonzero(z > 1e-6)[0]
    if len(off):
        print(f"off the wall from {t[off[0]]:.2f} to {t[off[-1]]:.2f} us, highest {z.max():.4f} mm")
    else:
        print("face centre stays on the wall")
    print(f"at {t[-1]:.2f} us: length {h[-1, 3] * 1e3:.3f} mm, largest radius {h[-1, 4] * 1e3:.3f} mm,"
          f" plastic strain at the face's centre {h[-1, 5]:.2f}")


if __name__ == "__main__":
    main()
