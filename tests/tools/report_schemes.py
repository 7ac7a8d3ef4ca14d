#!/usr/bin/python3
"""The report's five iteration schemes on one material point, from the report's equations.

    report_schemes.py case PATH VARIANT            the hencky case of PATH and VARIANT (stdout)
    report_schemes.py iterates PATH VARIANT        every iterate of the reference (stdout)
    report_schemes.py compare PATH VARIANT CSV     compares hencky's iterations.csv with it

PATH is one of the strain histories below (`proportional`, `turning`, `deep`, `thermal`); VARIANT one
of variable-stiffness, variable-stiffness-strain (curve form F = eps(sigma)), initial-strain,
initial-strain-stiffness, initial-stress, initial-stress-stiffness.

This is the independent side of issue 46's check of `solver.formulation: report`: it is
written from the report's equations (shared/seed/formulation-report-ru.md, section 2, and
shared/FORMULATION.md), with full 6x6 matrices where hencky's point laws use scalar shortcuts:
D~ = D (I - Y~), Y~ = Z (Z^T D) / (E* + Z^T D Z), E* = tan b* tan b^e / (tan b^e - tan b*)
(2.9)-(2.11), Z = M sigma(t) / sigma~(t) (2.10); the iterate's stress from (2.26); the
parameters of (2.33), (2.34), (2.37), (2.40), (2.43), (2.46); the thermal increment of (1.9)
with its (A1 - A0) sigma(t) term. What the report leaves open is decided as hencky's docs say
(docs/schemes.md, "formulation: report"), and these decisions are the only shared ground:
- the scalar increment of x = d_eps - d_eps_th is Z^T D x / 3G (signed); eps~(t) is the state
  these increments advanced where the step before ended at the largest eps~ reached, else the
  strain of sigma~(t) on the step's curve, F(sigma~(t)) (the kink where sigma~(t) is at or
  above the yield stress); sigma~(t) the von Mises stress;
- a stress at t below 1e-12 of the yield stress has no direction: Z is the trial's;
- elastic unloading: below the largest eps~ reached, the line of slope 3G(t+dt) through the
  curve's point there; tan b*_0 is the curve's slope at eps~(t) (its loading side when eps~(t)
  is the largest reached);
- a secant over an increment below 1e-8 of eps~ (of sigma~) is the slope there;
- the stress of iterate k that hencky reports is the one the next solve starts from (the step
  loop's residual form): sigma(t) + D~(b*_{k+1})(x - d_eps0_{k+1}) + d_sigma0_{k+1};
- the measures are |Delta_k| with sigma~ and eps~ those of that iterate, and 0 at a point
  elastic (plastic multiplier below 1e-12 of eps~) in this iterate and the one before;
- a step converges at the first iterate whose two measures are <= 1e-6.

The point is the one hexahedron of tests/cli/inputs/nl1/cube.geo with every degree of freedom
prescribed: its eight integration points are one material point, and hencky's global measures
are that point's. The material: linear hardening sigma_y(T) + h eps~p with the elastic
unloading of the report, E(T), nu, alpha (secant) constant. Standard library + numpy.
"""
import csv
import sys

import numpy as np

NU, ALPHA, H, T_REF = 0.3, 1.2e-5, 1e11, 20.0
E_TABLE = ([20.0, 320.0], [200e9, 170e9])
YIELD_TABLE = ([20.0, 320.0], [250e6, 200e6])
# The initial strains' relaxation: with the strain held a point's error changes by
# 1 - OMEGA * tan b* / tan b per iteration (tan b the curve's slope, tan b* the matrix's): with
# these values -0.1 to 0.7 where it flows, 0.91 where a -stiffness point unloads.
OMEGA = 0.3
MAX_ITERATIONS = 200
TOL = 1e-6
VARIANTS = ["variable-stiffness", "variable-stiffness-strain", "initial-strain",
            "initial-strain-stiffness", "initial-stress", "initial-stress-stiffness"]

# Strain histories: (times of the steps' ends, legs [(t_end, {component: value at t_end})]),
# components in Voigt order xx yy zz yz xz xy with engineering shears; piecewise linear in t.
PATHS = {
    # uniaxial strain: the stress deviator keeps its direction (a proportional path); loading,
    # unloading to half, reloading beyond
    "proportional": ([0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0],
                     [(1.0, {2: 0.004}), (1.5, {2: 0.002}), (2.0, {2: 0.005})]),
    # NAFEMS NL1's kind of path: a stretch, then a shear at the stretch held, then the
    # stretch taken back at the shear held
    "turning": ([1 / 3, 2 / 3, 1.0, 4 / 3, 5 / 3, 2.0, 7 / 3, 8 / 3, 3.0],
                [(1.0, {0: 0.003}), (2.0, {0: 0.003, 5: 0.006}), (3.0, {0: 0.0, 5: 0.006})]),
    # first yield deep within a step: the strain form's secant iteration (2.34), which a
    # held strain makes diverge where the secant exceeds twice the curve's slope (as at a
    # yield met early in a step: the paths above), converges
    "deep": ([1.0, 2.0, 3.0], [(1.0, {2: 0.006}), (2.0, {2: 0.008}), (3.0, {2: 0.004})]),
    # the proportional path while the temperature rises 20 -> 320 over t = 0 .. 2: E(T),
    # sigma_y(T) and the thermal strain change within every step
    "thermal": ([0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0],
                [(1.0, {2: 0.004}), (1.5, {2: 0.002}), (2.0, {2: 0.005})]),
}

M = np.array([[1, -.5, -.5, 0, 0, 0], [-.5, 1, -.5, 0, 0, 0], [-.5, -.5, 1, 0, 0, 0],
              [0, 0, 0, 3, 0, 0], [0, 0, 0, 0, 3, 0], [0, 0, 0, 0, 0, 3]], float)  # (1.19)
DELTA = np.array([1, 1, 1, 0, 0, 0], float)
PARAVIEW = [0, 1, 2, 5, 3, 4]  # xx yy zz xy yz xz of iterations.csv, in Voigt positions


def table(tab, t):
    return float(np.interp(t, tab[0], tab[1]))


def temperature(path, t):
    return 20.0 + 150.0 * t if path == "thermal" else T_REF


def strain(path, t):
    """The prescribed strain tensor (Voigt, engineering shears) at t."""
    legs = PATHS[path][1]
    e, t0 = np.zeros(6), 0.0
    for t1, values in legs:
        e1 = e.copy()
        for c, v in values.items():
            e1[c] = v
        if t <= t1:
            return e + (e1 - e) * (t - t0) / (t1 - t0)
        e, t0 = e1, t1
    return e


def stiffness(T):
    E = table(E_TABLE, T)
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D[:3, :3] += 2 * mu * np.eye(3)
    D[3:, 3:] = mu * np.eye(3)
    return D, 3 * mu


def von_mises(s):
    return float(np.sqrt(max(s @ M @ s, 0.0)))  # (1.18), c = 1


def d_tilde(D, Z, tan_b, three_g):
    """D~(b*) of (2.9)-(2.11); D itself for b* = b^e (2.13) or no direction."""
    zdz = Z @ D @ Z
    if tan_b == three_g or zdz <= 0:
        return D.copy()
    e_star = tan_b * three_g / (three_g - tan_b)  # (2.11)
    Y = np.outer(Z, Z @ D) / (e_star + zdz)  # (2.10)
    return D @ (np.eye(6) - Y)  # (2.9)


class Curve:
    """sigma~ = Phi(eps~) at T with slope 3G below the yield (linear hardening), and the
    report's elastic unloading: below eps_max the line of slope 3G through Phi(eps_max)."""

    def __init__(self, T, three_g, eps_max):
        self.y, self.g3 = table(YIELD_TABLE, T), three_g
        self.kink = max(eps_max, self.y / three_g)  # eps~ where the rising curve begins
        self.top = self.virgin(self.kink)

    def virgin(self, e):
        if e <= self.y / self.g3:
            return self.g3 * e
        return (self.y + H * e) / (1 + H / self.g3)  # sigma = y + h(eps - sigma/3G)

    def phi(self, e):
        return self.top - self.g3 * (self.kink - e) if e < self.kink else self.virgin(e)

    def phi_slope(self, e, right):
        if e < self.kink or (e == self.kink and not right):
            return self.g3
        return self.g3 * H / (self.g3 + H) if e >= self.y / self.g3 else self.g3

    def f(self, s):
        if s < self.top:
            return self.kink - (self.top - s) / self.g3
        return (s - self.y) / H + s / self.g3

    def f_slope(self, s):
        return 1 / self.g3 if s < self.top else 1 / H + 1 / self.g3


def run(path, variant):
    """Every iterate: rows (step, time, k, |Delta_sigma|, |Delta_eps|, sigma (6), eps~)."""
    scheme = variant.replace("-strain", "") if variant.endswith("stiffness-strain") else variant
    strain_form = variant in ("variable-stiffness-strain", "initial-strain",
                              "initial-strain-stiffness")
    times = PATHS[path][0]
    sigma, eps_t, eps_max, t_prev = np.zeros(6), 0.0, 0.0, 0.0
    rows = []
    for step, t in enumerate(times, 1):
        T0, T1 = temperature(path, t_prev), temperature(path, t)
        D0, _ = stiffness(T0)
        D, g3 = stiffness(T1)
        # (1.9): the thermal strain alpha T - alpha T_ref and the compliance's change on sigma(t)
        d_th = ALPHA * (T1 - T0) * DELTA + (np.linalg.inv(D) - np.linalg.inv(D0)) @ sigma
        x = strain(path, t) - strain(path, t_prev) - d_th
        curve = Curve(T1, g3, eps_max)
        q0 = von_mises(sigma)
        loading = eps_t >= eps_max
        if not loading:  # below the largest eps~ reached: the strain of sigma~(t) on the curve,
            eps_t = curve.f(q0) if q0 < curve.top else curve.kink  # the kink at or above it
        Z = M @ sigma / q0 if q0 > 1e-12 * curve.top else None
        if Z is None:  # no direction at t: the trial stress's
            trial = sigma + D @ x
            Z = M @ trial / von_mises(trial) if von_mises(trial) > 0 else np.zeros(6)
            tan0 = g3
        else:
            tan0 = curve.phi_slope(eps_t, loading)
        dx = (Z @ D @ x) / g3  # d_eps~_k: the same x at every iterate (all prescribed)
        stiff = scheme.endswith("stiffness") and scheme != "variable-stiffness"
        tb = tan0 if stiff else g3  # the fixed matrix's slope
        Db = d_tilde(D, Z, tb, g3)
        small_e = 1e-8 * max(abs(eps_t), curve.kink)
        small_s = 1e-8 * max(abs(q0), curve.top)
        tan_k, e0, s0 = (tan0 if scheme == "variable-stiffness" else tb), np.zeros(6), np.zeros(6)
        dx_prev, ds_prev, plastic_prev = 0.0, 0.0, False
        converged = False
        for k in range(MAX_ITERATIONS):
            if scheme == "variable-stiffness":
                d_sigma = d_tilde(D, Z, tan_k, g3) @ x  # (2.26), d_eps0 = d_sigma0 = 0
                ds = Z @ d_sigma
                if strain_form:  # (2.34)
                    fk = curve.f(q0 + ds)
                    n_eps, n_sig = fk - (eps_t + dx_prev), ds - ds_prev
                    den = fk - eps_t
                    tan_k = ds / den if abs(ds) > small_s and den != 0 else 1 / curve.f_slope(q0 + ds)
                else:  # (2.33)
                    ph = curve.phi(eps_t + dx)
                    n_sig, n_eps = ph - (q0 + ds), dx - dx_prev
                    tan_k = (ph - q0) / dx if abs(dx) > small_e else curve.phi_slope(eps_t, loading)
                sig_next = sigma + d_tilde(D, Z, tan_k, g3) @ x
            elif scheme.startswith("initial-strain"):  # (2.37), (2.40)
                ds = Z @ (Db @ (x - e0))
                fk = curve.f(q0 + ds)
                n_eps, n_sig = fk - (eps_t + dx), ds - ds_prev
                e0 = e0 + OMEGA * n_eps * Z
                sig_next = sigma + Db @ (x - e0)
            else:  # (2.43), (2.46)
                ds = Z @ (Db @ x + s0)
                ph = curve.phi(eps_t + dx)
                n_sig, n_eps = ph - (q0 + ds), dx - dx_prev
                tan_ss = (ph - q0) / dx if abs(dx) > small_e else curve.phi_slope(eps_t, loading)
                s0 = (d_tilde(D, Z, tan_ss, g3) - Db) @ x
                sig_next = sigma + Db @ x + s0
            e_k = eps_t + dx
            # the plastic multiplier along Z: what of D x the stress change does not carry
            lam = Z @ (D @ x - (sig_next - sigma)) / g3
            plastic = abs(lam) > 1e-12 * max(abs(e_k), curve.kink)
            if not plastic and not plastic_prev:
                n_sig = n_eps = 0.0
            plastic_prev = plastic
            m_sig, m_eps = abs(n_sig) / von_mises(sig_next), abs(n_eps) / abs(e_k)
            rows.append((step, t, k, m_sig, m_eps, sig_next, e_k))
            dx_prev, ds_prev = dx, ds
            if m_sig <= TOL and m_eps <= TOL:
                converged = True
                break
        if not converged:  # the step fails: the run stops (cutback: 0)
            break
        sigma, eps_t, eps_max, t_prev = sig_next, e_k, max(eps_max, e_k), t
    return rows


def displacement_expr(path, comp):
    """u = eps(t) x as an expression of x, y, z, t (engineering shears halved)."""
    legs = PATHS[path][1]

    def piece(c):  # the component c of eps(t), piecewise linear
        e_prev, t0, parts = 0.0, 0.0, []
        for t1, values in legs:
            e1 = values.get(c, e_prev)
            parts.append("t <= %.17g ? %.17g + (%.17g) * (t - %.17g) / %.17g" %
                         (t1, e_prev, e1 - e_prev, t0, t1 - t0))
            e_prev, t0 = e1, t1
        return "(" + " : ".join(parts) + " : %.17g)" % e_prev

    x, y, z = "x", "y", "z"
    terms = {0: [(0, x, 1), (5, y, .5), (4, z, .5)], 1: [(5, x, .5), (1, y, 1), (3, z, .5)],
             2: [(4, x, .5), (3, y, .5), (2, z, 1)]}[comp]
    used = [(c, v, f) for c, v, f in terms if any(c in vals for _, vals in legs)]
    if not used:
        return "0"
    return " + ".join("%g * %s * %s" % (f, piece(c), v) for c, v, f in used)


def case(path, variant):
    scheme = "variable-stiffness" if variant.startswith("variable") else variant
    form = "\n  curve_form: strain" if variant == "variable-stiffness-strain" else ""
    thermal = path == "thermal"
    u = ", ".join('%s: "%s"' % (a, displacement_expr(path, i)) for i, a in enumerate("xyz"))
    faces = "\n".join("  - {region: %s, displacement: {%s}}" % (f, u)
                      for f in ["x0", "x1", "y0", "y1", "z0", "z1"])
    E = ("{temperature: [%g, %g], value: [%.17g, %.17g]}" % (*E_TABLE[0], *E_TABLE[1])
         if thermal else "%.17g" % E_TABLE[1][0])
    Y = ("{temperature: [%g, %g], value: [%.17g, %.17g]}" % (*YIELD_TABLE[0], *YIELD_TABLE[1])
         if thermal else "%.17g" % YIELD_TABLE[1][0])
    return f"""# Written by tests/tools/report_schemes.py: path '{path}', scheme '{variant}'.
title: the report's {variant} on one material point, path {path}
mesh: {{file: cube.geo}}
materials:
  - name: steel
    E: {E}
    nu: {NU}
    alpha: {ALPHA}
    plasticity: {{linear: {{yield: {Y}, hardening: {H:.17g}}}}}
{"temperature: {reference: 20, field: '20 + 150 * t'}" if thermal else ""}
boundary:
{faces}
solver:
  scheme: {scheme}{form}
  formulation: report
  relaxation: {OMEGA}
  max_iterations: {MAX_ITERATIONS}
  tolerance: {TOL}
  cutback: 0
  times: [{", ".join("%.17g" % t for t in PATHS[path][0])}]
output:
  iterations: true
  probes:
    - {{name: c, point: [0.5, 0.5, 0.5]}}
"""


def compare(path, variant, csv_file):
    """hencky's iterates against the reference's: every iterate's measures and stress."""
    ref = run(path, variant)
    got = [r for r in csv.DictReader(open(csv_file)) if int(r["iteration"]) >= 1]
    problems = []
    if len(got) != len(ref):
        problems.append("%d iterates in hencky, %d in the reference" % (len(got), len(ref)))
    last = {}
    for r in ref:
        last[r[0]] = r[2]
    worst = 0.0
    for g, r in zip(got, ref):
        step, t, k, m_sig, m_eps, sig, e_k = r
        if int(g["attempt"]) != step or int(g["iteration"]) != k + 1:
            problems.append("step %d iterate %d: hencky's row is attempt %s iteration %s" %
                            (step, k, g["attempt"], g["iteration"]))
            break
        # every iterate's values (the first five of a step and its last to 1e-12; between them
        # the same bound holds here, the iteration being contractive)
        scale = max(von_mises(sig), 1.0)
        checks = [("Delta_sigma", float(g["delta_sigma"]), m_sig, 1.0),
                  ("Delta_eps", float(g["delta_epsilon"]), m_eps, 1.0),
                  ("eps~", float(g["c.equivalent_elastoplastic_strain"]), e_k, abs(e_k))]
        names = ["xx", "yy", "zz", "xy", "yz", "xz"]
        for n, pos in zip(names, PARAVIEW):
            checks.append(("sigma_" + n, float(g["c.stress." + n]), sig[pos], scale))
        for name, a, b, sc in checks:
            # a measure is a defect over sigma~ (eps~): to 1e-12 of that scale; a value to
            # 1e-12 of itself (a stress component of the von Mises stress)
            err = abs(a - b) / max(abs(b), sc)
            worst = max(worst, err)
            if err > 1e-12 and (k < 5 or k == last[step]):
                problems.append("step %d iterate %d: %s %.17g in hencky, %.17g in the reference"
                                " (%.2g relative)" % (step, k, name, a, b, err))
    for p in problems[:10]:
        print(p)
    print("%s %s: %d iterates in %d steps, largest difference %.2g relative" %
          (path, variant, len(ref), len(last), worst))
    return not problems


def main():
    what, path, variant = sys.argv[1:4]
    if path not in PATHS or variant not in VARIANTS:
        sys.exit("unknown path or variant")
    if what == "case":
        print(case(path, variant))
    elif what == "iterates":
        for step, t, k, m_sig, m_eps, sig, e_k in run(path, variant):
            print(step, "%.6g" % t, k, "%.6e %.6e" % (m_sig, m_eps),
                  " ".join("%.10e" % v for v in sig), "%.10e" % e_k)
    elif what == "compare":
        sys.exit(0 if compare(path, variant, sys.argv[4]) else 1)
    else:
        sys.exit("unknown command " + what)


if __name__ == "__main__":
    main()
