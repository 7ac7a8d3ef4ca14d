#!/usr/bin/python3
"""The exact answer of NAFEMS NL1 (tests/cli/inputs/nl1/case.yaml) at the end of each leg.

    nl1_reference.py [PLASTIC_MODULUS]        (Pa; 0, the default: perfectly plastic)

Prints one line per leg: the leg's end time, von Mises stress, sigma_xx, sigma_yy, sigma_zz
(Pa) and the equivalent plastic strain.

The material point follows a piecewise-linear strain history (plane strain, eps_z = 0) under
small-strain von Mises plasticity with linear isotropic hardening. Each leg is integrated with
the backward-Euler radial return in n and 2n equal sub-increments, n = 2^13, and the two are
extrapolated (Richardson, 2 X_2n - X_n): the return is first-order accurate on a path whose
direction changes, exact on a proportional one, so the extrapolated values are exact to about
1e-9 of sigma_y (those of n = 2^13, 2^14 and 2^15 agree to 1e-9 sigma_y; before extrapolation
the n and 2n runs differ by up to 2e-5 sigma_y at n = 2^13).
This is the rate problem itself, integrated independently of hencky's point law. Standard
library + numpy.
"""
import sys

import numpy as np

E, NU, SIGMA_Y = 250e9, 0.25, 5e6
T = [0, 1, 2, 3, 4, 5, 6, 7, 8]
EPS_X = [0, 2.5e-5, 5e-5, 5e-5, 5e-5, 2.5e-5, 0, 0, 0]
EPS_Y = [0, 0, 0, 2.5e-5, 5e-5, 5e-5, 5e-5, 2.5e-5, 0]


def integrate(h, n):
    """[von Mises, sxx, syy, szz, eps_p_eq] at each leg's end, n sub-increments a leg."""
    g, k = E / (2 * (1 + NU)), E / (3 * (1 - 2 * NU))
    dev = np.zeros(3)  # the stress deviator's diagonal (no shear on this path)
    mean, eps_p = 0.0, 0.0
    out = []
    for leg in range(len(T) - 1):
        d = np.array([EPS_X[leg + 1] - EPS_X[leg], EPS_Y[leg + 1] - EPS_Y[leg], 0.0]) / n
        dv = d.sum()
        for _ in range(n):
            mean += k * dv
            trial = dev + 2 * g * (d - dv / 3)
            q = np.sqrt(1.5 * trial @ trial)
            f = q - (SIGMA_Y + h * eps_p)
            if f > 0:
                dl = f / (3 * g + h)
                trial *= 1 - 3 * g * dl / q
                eps_p += dl
            dev = trial
        out.append([np.sqrt(1.5 * dev @ dev), *(dev + mean), eps_p])
    return np.array(out)


def main():
    h = float(sys.argv[1]) if len(sys.argv) > 1 else 0.0
    n = 2 ** 13
    coarse, fine = integrate(h, n), integrate(h, 2 * n)
    for t, row in zip(T[1:], 2 * fine - coarse):
        print(t, " ".join("%.10e" % v for v in row))


if __name__ == "__main__":
    main()
