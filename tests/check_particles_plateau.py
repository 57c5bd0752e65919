#!/usr/bin/env python3
"""The solid's plateau of a gas / linear-elastic solid Riemann problem run
with Euler steps (its particles cross cells), against the exact solution of
tools/exact/gas_solid.py: a quasi-1D run along x, gas on the left of X0,
coupled particles on the right.

    check_particles_plateau.py FRAME RHO U P GAMMA RHO_S U_S SXX M X0 MEAN_TOL SCATTER_TOL U_TOL

In the plateau between the interface and the solid's front (the particles
with X0 + u* t + 0.05 < x < X0 + c_L t - 0.2: clear of the interface cell
and of the front's ringing, which are not what this checks) the particles'
traction -sigma_xx must have a mean within MEAN_TOL of p* (relative) and a
standard deviation at most SCATTER_TOL of p*; their mean velocity within
U_TOL of u* (relative). Prints every number.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "exact"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
sys.dont_write_bytecode = True
from gas_solid import GasSolidSolution  # noqa: E402
from particles_euler import plateau  # noqa: E402


def main():
    frame = sys.argv[1]
    rho, u, p, g, rho_s, u_s, sxx, modulus, x0, mean_tol, scatter_tol, u_tol = (float(v) for v in sys.argv[2:14])
    sol = GasSolidSolution((rho, u, p, g), (rho_s, u_s, sxx, modulus), gas_side="left")
    t, n, mean, scatter, umean = plateau(frame, sol, x0)
    lo = x0 + sol.u_star * t + 0.05
    hi = x0 + sol.solid_front * t - 0.2
    if n < 20:
        sys.exit(f"FAIL: only {n} particles in the plateau {lo:.4g} < x < {hi:.4g} at t = {t:.4g}")
    checks = [("traction mean / p* - 1", mean, abs(mean) <= mean_tol, f"|.| <= {mean_tol}"),
              ("traction scatter (std) / p*", scatter, scatter <= scatter_tol, f"<= {scatter_tol}"),
              ("velocity mean / u* - 1", umean, abs(umean) <= u_tol, f"|.| <= {u_tol}")]
    print(f"{os.path.basename(frame)}: t = {t:.6g}, p* = {sol.p_star:.6g}, u* = {sol.u_star:.6g}, "
          f"{n} particles in {lo:.4g} < x < {hi:.4g}")
    ok = True
    for name, value, good, bound in checks:
        ok = ok and good
        print(f"  {name}: {value:+.4e} ({bound})  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
