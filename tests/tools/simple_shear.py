#!/usr/bin/python3
"""Finite simple shear of a von Mises solid with Hencky's elasticity: the reference of
tests/cli/inputs/updated/shear.

    simple_shear.py E NU SIGMA_Y H GAMMA [STEPS]

prints "gamma sigma_xx sigma_yy sigma_zz sigma_xy eps_p" at GAMMA/4, GAMMA/2, 3 GAMMA/4 and
GAMMA. The material is hencky's under `solver.geometry: updated` (docs/schemes.md): the
multiplicative split F = Fe Fp, the elastic logarithmic strain 1/2 ln be, the Kirchhoff stress
tau = 2G dev(eps_e) + K tr(eps_e) I, the yield surface sqrt(3/2)|dev tau| = sigma_y + H eps_p,
the plastic flow along dev tau (no plastic spin). The motion is F = I + gamma e_x (x) e_y; it
is isochoric, so the Cauchy stress is tau. The flow is integrated by the exponential map over
STEPS equal increments of gamma (default 100000): an independent implementation (numpy's
eigh, no code of hencky's) of the continuum solution, whose error falls with the increment
(run with 10000 and 100000 to see it: the difference is the error of the 10000).

As the elastic strains vanish (sigma_y/E -> 0) the answer tends to the rigid-plastic
solution of simple shear (Hill, The Mathematical Theory of Plasticity, 1950, ch. on the
plastic-rigid solid): a pure shear stress sigma_xy = (sigma_y + H eps_p)/sqrt 3 with
eps_p = gamma/sqrt 3, and no normal stress; main() prints that too.
Standard library + numpy.
"""
import math
import sys

import numpy as np


def sym_fun(a, f):
    w, v = np.linalg.eigh(a)
    return (v * f(w)) @ v.T


def shear(E, nu, sy, H, gamma, steps=100000, marks=4):
    G = E / (2 * (1 + nu))
    K = E / (3 * (1 - 2 * nu))
    be = np.eye(3)
    ep = 0.0
    f = np.eye(3)
    f[0, 1] = gamma / steps
    out = []
    for k in range(1, steps + 1):
        eps = 0.5 * sym_fun(f @ be @ f.T, np.log)
        tr = np.trace(eps)
        dev = eps - tr / 3 * np.eye(3)
        s = 2 * G * dev
        q = math.sqrt(1.5 * np.sum(s * s))
        yield_now = sy + H * ep
        if q > yield_now:
            dl = (q - yield_now) / (3 * G + H)
            eps = eps - dl * 1.5 * s / q
            ep += dl
            s = s * (1 - 3 * G * dl / q)
        be = sym_fun(2 * eps, np.exp)
        if k * marks % steps == 0:
            tau = s + K * tr * np.eye(3)
            out.append((gamma * k / steps, tau[0, 0], tau[1, 1], tau[2, 2], tau[0, 1], ep))
    return out


def main():
    E, nu, sy, H, gamma = (float(a) for a in sys.argv[1:6])
    steps = int(sys.argv[6]) if len(sys.argv) > 6 else 100000
    for row in shear(E, nu, sy, H, gamma, steps):
        print(" ".join(f"{v:.10g}" for v in row))
    ep = gamma / math.sqrt(3)
    print(f"rigid-plastic at gamma = {gamma:g}: sigma_xy = {(sy + H * ep) / math.sqrt(3):.10g}, "
          f"eps_p = {ep:.10g}")


if __name__ == "__main__":
    main()
