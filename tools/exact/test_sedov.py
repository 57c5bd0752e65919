#!/usr/bin/python3
"""Checks of tools/exact/sedov.py (plain script; exit status 1 on failure).

Run:  /usr/bin/python3 tools/exact/test_sedov.py

References used
---------------
KT = Kamm & Timmes (2007), "On efficient generation of numerically robust
Sedov solutions", LA-UR-07-2849:
  * Tables 1-3: similarity functions V, f, g, h at given lambda for
    gamma = 1.4, planar / cylindrical / spherical (4 printed decimals).
  * Table 4: energy integrals J1, J2 and alpha for gamma = 1.4, and the test
    problem energies E = 0.0673185 (planar), 0.311357 (cylindrical),
    0.851072 (spherical) at rho0 = 1, t = 1, which put the shock at
    r2 = 0.5, 0.75, 1.0 (Table 5).
  * Convention: alpha = (J1 + 2 J2/(gamma-1))/2 for planar (so E is the
    energy per unit area of the half-space x >= 0, sigma_1 = 1),
    alpha = (j-1) pi (J1 + 2 J2/(gamma-1)) for j = 2, 3 (E per unit length /
    total).  Table 4's alpha values for gamma = 1.4 are 0.538548 (planar),
    0.984041 (cylindrical), 0.851060 (spherical).
Sedov constant xi0 = alpha^(-1/5) for the spherical blast: 1.15167 for
gamma = 5/3 (e.g. Ostriker & McKee 1988, Rev. Mod. Phys. 60, 1), about
1.033 for gamma = 1.4 (Taylor 1950; Sedov 1959).

Accuracy note: our J1 agree with KT Table 4 to the printed digits, but our
J2 are larger by 4e-4 (planar), 4e-5 (cylindrical), 2e-5 (spherical),
relative.  KT's J2 integrand in V is singular at the centre, most strongly
for planar; the independent checks below (energy by direct quadrature in r,
PDE residuals, mass conservation, KT Tables 1-3) support our values.  The
Table 4 alpha and J2 values (and the planar E = 0.0673185, which is
0.538548 / 8) are therefore checked at relative 5e-4 only, while the
spherical 0.851072 (KT's spherical test energy, consistent with our alpha to
1e-7) and the cylindrical 0.984074 (the value given in the task
specification; source not independently verified, KT Table 4 prints
0.984041) are checked at 1e-6.
"""

import os as _os
import sys as _sys
_sys.path.insert(0, _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__))))
import debian_python  # noqa: E402  (tools/debian_python.py)
debian_python.require("numpy", "scipy")

import math
import os
import sys
import time

import numpy as np
from scipy.integrate import quad

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sedov import SedovSolution  # noqa: E402

FAILURES = []


def check(cond, msg):
    print(("ok    " if cond else "FAIL  ") + msg)
    if not cond:
        FAILURES.append(msg)


def rel(a, b):
    return abs(a - b) / abs(b)


SIGMA = {1: 1.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}
NAME = {1: "planar", 2: "cylindrical", 3: "spherical"}


def radial_integrals(sol, t, npanel=1000, order=20):
    """Mass and energy inside the shock by composite Gauss-Legendre in r."""
    j, g = sol.geometry, sol.gamma
    r2 = sol.shock_radius(t)
    edges = np.linspace(0.0, r2, npanel + 1)
    x, w = np.polynomial.legendre.leggauss(order)
    a, b = edges[:-1], edges[1:]
    r = (0.5 * (a + b))[:, None] + (0.5 * (b - a))[:, None] * x
    wr = (0.5 * (b - a))[:, None] * w * r ** (j - 1) * SIGMA[j]
    rho, u, p = sol.state(r, t)
    mass = np.sum(wr * rho)
    energy = np.sum(wr * (0.5 * rho * u * u + p / (g - 1.0)))
    return mass, energy


# ----------------------------------------------------------------------------
def test_alpha():
    print("-- energy integrals")
    kt = {  # KT Table 4, gamma = 1.4: J1, J2, alpha
        1: (0.197928, 0.175834, 0.538548),
        2: (6.54053e-2, 4.95650e-2, 0.984041),
        3: (2.96269e-2, 2.11647e-2, 0.851060),
    }
    for j in (1, 2, 3):
        s = SedovSolution(1.4, j, 1.0)
        J1, J2, al = kt[j]
        print("   gamma 1.4 %-11s alpha = %.7f  J1 = %.7g  J2 = %.7g"
              % (NAME[j], s.alpha, s.J1, s.J2))
        check(abs(s.J1 - J1) < 1.5e-6 * max(1.0, J1 / 0.1),
              "J1 %s = %.7g vs KT Table 4 %.6g" % (NAME[j], s.J1, J1))
        check(rel(s.J2, J2) < 5e-4,
              "J2 %s = %.7g vs KT Table 4 %.6g (rel 5e-4)" % (NAME[j], s.J2, J2))
        check(rel(s.alpha, al) < 5e-4,
              "alpha %s = %.7f vs KT Table 4 %.6f (rel 5e-4)"
              % (NAME[j], s.alpha, al))
        # KT's alpha convention, from our J1, J2
        conv = (0.5 if j == 1 else (j - 1) * math.pi) * (s.J1 + 2 * s.J2 / 0.4)
        check(rel(s.alpha, conv) < 1e-12, "alpha %s = KT combination of J1, J2"
              % NAME[j])
    s3 = SedovSolution(1.4, 3, 1.0)
    check(rel(s3.alpha, 0.851072) < 1e-6,
          "alpha spherical 1.4 = %.7f vs 0.851072 (KT spherical test E)" % s3.alpha)
    s2 = SedovSolution(1.4, 2, 1.0)
    check(rel(s2.alpha, 0.984074) < 1e-6,
          "alpha cylindrical 1.4 = %.7f vs 0.984074 (task spec)" % s2.alpha)
    check(abs(s3.alpha ** -0.2 - 1.033) < 1e-3,
          "xi0 spherical 1.4 = %.6f vs 1.033" % s3.alpha ** -0.2)
    s53 = SedovSolution(5.0 / 3.0, 3, 1.0)
    check(abs(s53.alpha ** -0.2 - 1.15167) < 1e-5,
          "xi0 spherical 5/3 = %.6f vs 1.15167" % s53.alpha ** -0.2)
    for j in (1, 2, 3):
        s = SedovSolution(5.0 / 3.0, j, 1.0)
        print("   gamma 5/3 %-11s alpha = %.7f  J1 = %.7g  J2 = %.7g"
              % (NAME[j], s.alpha, s.J1, s.J2))


def test_similarity_tables():
    print("-- KT Tables 1-3 (gamma 1.4), printed to 4 decimals")
    tables = {
        1: ([0.9797, 0.9420, 0.9013, 0.8565, 0.8050, 0.7419, 0.7029, 0.6553,
             0.5925, 0.5396, 0.4912, 0.4589, 0.4161, 0.3480, 0.2810, 0.2320,
             0.1680, 0.1040],
            [0.5500, 0.5400, 0.5300, 0.5200, 0.5100, 0.5000, 0.4950, 0.4900,
             0.4850, 0.4820, 0.4800, 0.4790, 0.4780, 0.4770, 0.4765, 0.4763,
             0.4762, 0.4762],
            [0.9699, 0.9157, 0.8598, 0.8017, 0.7390, 0.6677, 0.6263, 0.5780,
             0.5173, 0.4682, 0.4244, 0.3957, 0.3580, 0.2988, 0.2410, 0.1989,
             0.1440, 0.0891],
            [0.8620, 0.6662, 0.5159, 0.3981, 0.3020, 0.2201, 0.1823, 0.1453,
             0.1075, 0.0826, 0.0641, 0.0535, 0.0415, 0.0263, 0.0153, 0.0095,
             0.0042, 0.0013],
            [0.9159, 0.7917, 0.6922, 0.6119, 0.5458, 0.4905, 0.4661, 0.4437,
             0.4230, 0.4112, 0.4037, 0.4001, 0.3964, 0.3929, 0.3911, 0.3905,
             0.3901, 0.3900]),
        2: ([0.9998, 0.9802, 0.9644, 0.9476, 0.9295, 0.9096, 0.8725, 0.8442,
             0.8094, 0.7629, 0.7242, 0.6894, 0.6390, 0.5745, 0.5180, 0.4748,
             0.4222, 0.3654, 0.3000, 0.2500, 0.2000, 0.1500, 0.1000],
            [0.4166, 0.4100, 0.4050, 0.4000, 0.3950, 0.3900, 0.3820, 0.3770,
             0.3720, 0.3670, 0.3640, 0.3620, 0.3600, 0.3585, 0.3578, 0.3575,
             0.3573, 0.3572, 0.3572, 0.3571, 0.3571, 0.3571, 0.3571],
            [0.9996, 0.9645, 0.9374, 0.9097, 0.8812, 0.8514, 0.7999, 0.7638,
             0.7226, 0.6720, 0.6327, 0.5990, 0.5521, 0.4943, 0.4448, 0.4074,
             0.3620, 0.3133, 0.2572, 0.2143, 0.1714, 0.1286, 0.0857],
            [0.9972, 0.7651, 0.6281, 0.5161, 0.4233, 0.3450, 0.2427, 0.1892,
             0.1415, 0.0974, 0.0718, 0.0545, 0.0362, 0.0208, 0.0123, 0.0079,
             0.0044, 0.0021, 0.0008, 0.0003, 0.0001, 0.0000, 0.0000],
            [0.9984, 0.8658, 0.7829, 0.7122, 0.6513, 0.5982, 0.5266, 0.4884,
             0.4545, 0.4241, 0.4074, 0.3969, 0.3867, 0.3794, 0.3760, 0.3746,
             0.3737, 0.3732, 0.3730, 0.3729, 0.3729, 0.3729, 0.3729]),
        3: ([0.9913, 0.9773, 0.9622, 0.9342, 0.9080, 0.8747, 0.8359, 0.7950,
             0.7493, 0.6788, 0.5794, 0.4560, 0.3600, 0.2960, 0.2000, 0.1040],
            [0.3300, 0.3250, 0.3200, 0.3120, 0.3060, 0.3000, 0.2950, 0.2915,
             0.2890, 0.2870, 0.2860, 0.2857, 0.2857, 0.2857, 0.2857, 0.2857],
            [0.9814, 0.9529, 0.9238, 0.8745, 0.8335, 0.7872, 0.7398, 0.6952,
             0.6497, 0.5844, 0.4971, 0.3909, 0.3086, 0.2537, 0.1714, 0.0891],
            [0.8388, 0.6454, 0.4984, 0.3248, 0.2275, 0.1508, 0.0968, 0.0620,
             0.0379, 0.0174, 0.0052, 0.0009, 0.0001, 0.0000, 0.0000, 0.0000],
            [0.9116, 0.7992, 0.7082, 0.5929, 0.5238, 0.4674, 0.4273, 0.4021,
             0.3857, 0.3732, 0.3672, 0.3656, 0.3655, 0.3655, 0.3655, 0.3655]),
    }
    for j, (lam, v, f, g, h) in tables.items():
        s = SedovSolution(1.4, j, 1.0)
        V, F, G, H = s.similarity(lam)
        err = max(np.max(np.abs(a - np.array(b)))
                  for a, b in ((V, v), (F, f), (G, g), (H, h)))
        # 4-decimal rounding of the table: |error| <= 5e-5 (+ round-off)
        check(err < 6e-5, "KT Table %d (%s): max |error| in V,f,g,h = %.2e"
              % (j, NAME[j], err))
        lam2, F2, G2, H2 = s.functions_of_v(V)
        # (near the centre V - V0 ~ 1e-11: lambda(V) is ill-conditioned)
        check(np.allclose(lam2, lam, rtol=1e-6) and np.allclose(F2, F, rtol=1e-6)
              and np.allclose(H2, H, rtol=1e-9),
              "functions_of_v inverts similarity (%s)" % NAME[j])


def test_shock_and_standard_problems():
    print("-- shock position and post-shock state")
    g = 1.4
    s = SedovSolution(g, 3, 0.851072, rho0=1.0)
    r2 = s.shock_radius(1.0)
    check(abs(r2 - 1.0) < 1e-6, "spherical E=0.851072: r2(1) = %.9f" % r2)
    D = 0.4 * r2 / 1.0
    rho, u, p = s.state(np.array([r2 * (1 - 1e-12), r2 * (1 + 1e-12)]), 1.0)
    check(rel(rho[0], 6.0) < 1e-6, "rho just inside = %.9f vs 6" % rho[0])
    check(rel(u[0], 2 * D / (g + 1)) < 1e-6,
          "u just inside = %.9f vs 2D/(g+1) = %.9f" % (u[0], 2 * D / (g + 1)))
    check(rel(p[0], 2 * D * D / (g + 1)) < 1e-6,
          "p just inside = %.9f vs 2 rho0 D^2/(g+1) = %.9f"
          % (p[0], 2 * D * D / (g + 1)))
    check(rho[1] == 1.0 and u[1] == 0.0 and p[1] == 0.0, "ambient just outside")
    rr, uu, pp = s.state(np.array([0.0, 0.7493, 2.0]), 1.0)
    print("   spherical 1.4 at t=1: r=0: rho %.3g u %.3g p %.6f;  r=0.7493: "
          "rho %.6f u %.6f p %.6f (KT Table 3, lambda 0.7493: g 0.0379, "
          "f 0.6497, h 0.3857)" % (rr[0], uu[0], pp[0], rr[1], uu[1], pp[1]))
    check(rr[0] == 0.0 and uu[0] == 0.0 and rel(pp[0], 0.3655 * 0.4 ** 2
                                                 * 2 / 2.4) < 2e-4,
          "centre: rho = u = 0, p = p2 h(0) (h(0) = 0.3655, KT Table 3)")
    check(abs(rr[1] / 6.0 - 0.0379) < 6e-5 and abs(uu[1] / u[0] - 0.6497) < 6e-5
          and abs(pp[1] / p[0] - 0.3857) < 6e-5,
          "r = 0.7493: rho/rho2, u/u2, p/p2 = KT Table 3 g, f, h")

    # KT Table 5 standard cases (t = 1, rho0 = 1): r2 = 0.5, 0.75, 1.0
    for j, E, r2ref, tol in ((1, 0.0673185, 0.5, 2e-4),
                             (2, 0.311357, 0.75, 2e-5),
                             (3, 0.851072, 1.0, 1e-6)):
        s = SedovSolution(1.4, j, E)
        r2 = s.shock_radius(1.0)
        check(rel(r2, r2ref) < tol, "KT %s test: r2(1) = %.7f vs %.2f (rel %g)"
              % (NAME[j], r2, r2ref, tol))
        rho2, u2, p2 = s.post_shock(1.0)
        D = 2.0 / (j + 2) * r2
        check(rel(rho2, 6.0) < 1e-14 and rel(u2, D / 1.2) < 1e-14
              and rel(p2, D * D / 1.2) < 1e-14,
              "%s post-shock rho2 = %g u2 = %.6f p2 = %.6f"
              % (NAME[j], rho2, u2, p2))
    # KT Table 5 planar: u2 = 0.277778, p2 = 0.0925926 for r2 = 0.5 exactly
    s = SedovSolution(1.4, 1, 0.538548 * 0.125)
    s.alpha = 0.538548  # KT's alpha, to reproduce their r2 = 0.5 exactly
    _, u2, p2 = s.post_shock(1.0)
    check(abs(u2 - 0.277778) < 1e-6 and abs(p2 - 0.0925926) < 1e-7,
          "KT Table 5 planar u2 = %.6f p2 = %.7f" % (u2, p2))


def test_conservation():
    print("-- mass and energy inside the shock (quadrature in r)")
    for g in (1.4, 5.0 / 3.0):
        for j in (1, 2, 3):
            for (E, rho0, t) in ((1.0, 1.0, 1.0), (0.37, 2.5, 0.61)):
                s = SedovSolution(g, j, E, rho0=rho0)
                r2 = s.shock_radius(t)
                mass, energy = radial_integrals(s, t)
                swept = rho0 * SIGMA[j] * r2 ** j / j
                check(rel(mass, swept) < 1e-6 and rel(energy, E) < 1e-6,
                      "gamma %.4f %-11s E %.2f rho0 %.1f t %.2f: mass rel err "
                      "%.1e, energy rel err %.1e"
                      % (g, NAME[j], E, rho0, t, rel(mass, swept),
                         rel(energy, E)))


def test_pde_residuals():
    print("-- Euler equations satisfied (centred differences)")
    for g in (1.4, 5.0 / 3.0):
        for j in (1, 2, 3):
            s = SedovSolution(g, j, 0.7, rho0=1.3)
            t = 0.8
            R = s.shock_radius(t)
            r = R * np.array([0.5, 0.8, 0.95, 0.99])
            h, dt = 1e-5 * R, 1e-5 * t
            rho, u, p = s.state(r, t)
            rp, rm = s.state(r + h, t), s.state(r - h, t)
            tp, tm = s.state(r, t + dt), s.state(r, t - dt)

            def dr(k):
                return (rp[k] - rm[k]) / (2 * h)

            def dtt(k):
                return (tp[k] - tm[k]) / (2 * dt)

            div = dr(1) + (j - 1) * u / r
            cont = dtt(0) + u * dr(0) + rho * div
            mom = dtt(1) + u * dr(1) + dr(2) / rho
            ent = dtt(2) + u * dr(2) + g * p * div
            res = max(np.max(np.abs(cont)) / np.max(np.abs(rho * div)),
                      np.max(np.abs(mom)) / np.max(np.abs(dr(2) / rho)),
                      np.max(np.abs(ent)) / np.max(np.abs(g * p * div)))
            check(res < 1e-5, "gamma %.4f %-11s: max relative residual %.1e"
                  % (g, NAME[j], res))


def test_cell_average():
    print("-- cell averages")
    for g in (1.4, 5.0 / 3.0):
        for j in (1, 2, 3):
            s = SedovSolution(g, j, 1.0, rho0=1.7)
            t = 1.0
            R = s.shock_radius(t)
            edges = np.linspace(0.0, 1.3 * R + 0.00123, 97)
            rho, u, p = s.cell_average(edges, t)
            vol = SIGMA[j] * (edges[1:] ** j - edges[:-1] ** j) / j
            mass = np.sum(rho * vol)
            swept = 1.7 * SIGMA[j] * edges[-1] ** j / j
            mom_c = np.sum(rho * u * vol)
            # momentum by fine composite quadrature of the pointwise solution
            x, w = np.polynomial.legendre.leggauss(20)
            fe = np.linspace(0.0, R, 2001)
            a, b = fe[:-1], fe[1:]
            rr = (0.5 * (a + b))[:, None] + (0.5 * (b - a))[:, None] * x
            ww = (0.5 * (b - a))[:, None] * w * SIGMA[j] * rr ** (j - 1)
            r_, u_, p_ = s.state(rr, t)
            mom_f = np.sum(ww * r_ * u_)
            out = edges[:-1] >= R
            ok = (rel(mass, swept) < 1e-10 and rel(mom_c, mom_f) < 1e-8
                  and np.allclose(rho[out], 1.7, rtol=1e-13, atol=0)
                  and np.all(u[out] == 0.0)
                  and np.all(p[out] == 0.0))
            # one interior cell against scipy quad of the pointwise solution
            i = int(0.6 * R / edges[1])
            lo, hi = edges[i], edges[i + 1]

            def q(fun):
                return quad(lambda x: fun(x) * x ** (j - 1), lo, hi,
                            epsabs=0.0, epsrel=1e-12)[0]

            def st(x, k):
                return float(s.state(np.array([x]), t)[k][0])

            m = q(lambda x: st(x, 0))
            vj = (hi ** j - lo ** j) / j
            ok_i = (rel(rho[i], m / vj) < 1e-10
                    and rel(u[i], q(lambda x: st(x, 0) * st(x, 1)) / m) < 1e-10
                    and rel(p[i], q(lambda x: st(x, 2)) / vj) < 1e-10)
            check(ok and ok_i, "gamma %.4f %-11s: mass rel %.1e, momentum rel "
                  "%.1e, ambient cells exact, cell %d vs quad"
                  % (g, NAME[j], rel(mass, swept), rel(mom_c, mom_f), i))
    # planar, cells straddling x = 0 and both shocks
    s = SedovSolution(1.4, 1, 0.0673185)
    edges = np.linspace(-0.7, 0.7, 72)   # odd number of cells, 0 inside one
    rho, u, p = s.cell_average(edges, 1.0)
    check(rel(np.sum(rho * np.diff(edges)), 1.4) < 1e-10
          and np.allclose(rho, rho[::-1], rtol=1e-12)
          and np.allclose(u, -u[::-1], rtol=1e-12, atol=1e-15)
          and abs(u[35]) < 1e-15,
          "planar symmetric slab: mass, symmetry, u = 0 in the centre cell")


def test_errors():
    print("-- argument checking")
    for args, kw in (((1.4, 3, 1.0), {"omega": 1.0}), ((1.4, 4, 1.0), {}),
                     ((1.0, 3, 1.0), {}), ((1.4, 3, -1.0), {}),
                     ((2.0, 2, 1.0), {})):
        try:
            SedovSolution(*args, **kw)
            raised = False
        except ValueError:
            raised = True
        check(raised, "ValueError for %r %r" % (args, kw))


def main():
    t0 = time.time()
    test_alpha()
    test_similarity_tables()
    test_shock_and_standard_problems()
    test_conservation()
    test_pde_residuals()
    test_cell_average()
    test_errors()
    print("time %.2f s" % (time.time() - t0))
    if FAILURES:
        print("FAIL test_sedov: %d check(s) failed" % len(FAILURES))
        sys.exit(1)
    print("PASS test_sedov")


if __name__ == "__main__":
    main()
