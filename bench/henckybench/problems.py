"""The benchmark problems: material, geometry (Gmsh .geo text), closed forms and reference
solutions, and hencky's case files.

  - elastic (run_bench.py): a cantilever (Timoshenko) and a thick cylinder (Lamé, plane strain);
  - plastic (run_plastic_bench.py): the thick cylinder, elastic-perfectly plastic or with linear
    hardening, as a slice (Hill's closed form, a 1D reference solved along the radius);
  - contact (run_contact_bench.py): a rigid sphere pressed into an elastic block (Hertz).

PROBLEMS maps a problem's name to what gmsh.size_for needs to mesh it (`geo`: h -> .geo text,
`h_calib`: the size of its first mesh) and, for the elastic problems, the probe and its closed
form; plastic_problem and contact_problem register the other geometries.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

# ----------------------------------------------------------------------------------------------
# Elastic problems
# ----------------------------------------------------------------------------------------------
E = 2.1e11
NU = 0.3

# Cantilever: 1 x 0.1 x 0.1 m, clamped at x = 0 (all components), total end force P in -z
# spread uniformly over the end face x = L. Probe: centre of the end face (a mesh node: the
# point is embedded in the end surface).
CANT = dict(L=1.0, W=0.1, H=0.1, P=1000.0)

# Thick cylinder: quarter of a ring a < r < b, axial length Lz; symmetry planes x = 0, y = 0;
# both end faces held axially (u_z = 0: plane strain); internal pressure p. Probe: the bore
# vertex (a, 0, 0) (a geometry point, hence a mesh node). Radial displacement = u_x there.
CYL = dict(a=0.1, b=0.2, Lz=0.1, p=100e6)


def timoshenko_tip_deflection() -> float:
    """Tip deflection of a cantilever with an end load: bending + shear (Timoshenko beam)."""
    L, W, H, P = CANT["L"], CANT["W"], CANT["H"], CANT["P"]
    I = W * H**3 / 12.0
    A = W * H
    G = E / (2 * (1 + NU))
    kappa = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper's shear coefficient, rectangle
    return P * L**3 / (3 * E * I) + P * L / (kappa * G * A)


def lame_bore_displacement() -> float:
    """Radial displacement of the bore of a thick cylinder, plane strain (Lamé)."""
    a, b, p = CYL["a"], CYL["b"], CYL["p"]
    A = p * a**2 / (b**2 - a**2)
    B = p * a**2 * b**2 / (b**2 - a**2)
    return (1 + NU) / E * ((1 - 2 * NU) * A * a + B / a)


def geo_cantilever(h: float) -> str:
    c = CANT
    return f"""// hencky benchmark: cantilever {c['L']} x {c['W']} x {c['H']} m, element size h
L = {c['L']}; W = {c['W']}; H = {c['H']}; h = {h!r};
Point(1) = {{0, 0, 0, h}}; Point(2) = {{0, W, 0, h}}; Point(3) = {{0, W, H, h}}; Point(4) = {{0, 0, H, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
out[] = Extrude {{L, 0, 0}} {{ Surface{{1}}; }};
Point(100) = {{L, W/2, H/2, h}};
Point{{100}} In Surface{{out[0]}};   // a node at the centre of the end face (the probe)
Physical Volume("beam") = {{out[1]}};
Physical Surface("fixed") = {{1}};
Physical Surface("tip") = {{out[0]}};
Mesh.MeshSizeMax = h;
"""


def geo_cylinder(h: float, c: dict = CYL, layers: int = 0) -> str:
    """Quarter ring a < r < b, axial length Lz (the keys of CYL; the plastic benchmark passes
    its own), meshed with unstructured tetrahedra of size h; with `layers` > 0 meshed in its
    plane and extruded in that many layers (Gmsh splits each prism into three tetrahedra)."""
    extrude = f" Layers{{{layers}}};" if layers > 0 else ""
    return f"""// hencky benchmark: quarter thick cylinder a={c['a']} b={c['b']} length {c['Lz']}, element size h
a = {c['a']}; b = {c['b']}; Lz = {c['Lz']}; h = {h!r};
Point(1) = {{0, 0, 0, h}};
Point(2) = {{a, 0, 0, h}}; Point(3) = {{b, 0, 0, h}};
Point(4) = {{0, b, 0, h}}; Point(5) = {{0, a, 0, h}};
Line(1) = {{2, 3}};            // on y = 0
Circle(2) = {{3, 1, 4}};       // outer
Line(3) = {{4, 5}};            // on x = 0
Circle(4) = {{5, 1, 2}};       // bore
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
out[] = Extrude {{0, 0, Lz}} {{ Surface{{1}};{extrude} }};
// out[0] top, out[1] volume, out[2..5] lateral faces from lines 1..4
Physical Volume("wall") = {{out[1]}};
Physical Surface("bottom") = {{1}};
Physical Surface("top") = {{out[0]}};
Physical Surface("sym_y") = {{out[2]}};
Physical Surface("outer") = {{out[3]}};
Physical Surface("sym_x") = {{out[4]}};
Physical Surface("bore") = {{out[5]}};
Mesh.MeshSizeMax = h;
"""


def cylinder_boundary_yaml(pressure: str) -> str:
    """The hencky boundary block of the quarter cylinder (geo_cylinder's regions): `pressure`
    (a number or a quoted expression) on the bore, symmetry rollers, both end faces held
    axially."""
    return f"""boundary:
  - region: bore
    pressure: {pressure}
  - region: sym_x
    displacement: {{x: 0}}
  - region: sym_y
    displacement: {{y: 0}}
  - region: bottom
    displacement: {{z: 0}}
  - region: top
    displacement: {{z: 0}}
"""


PROBLEMS = {
    "cantilever": dict(
        geo=geo_cantilever,
        probe=(CANT["L"], CANT["W"] / 2, CANT["H"] / 2),
        exact=timoshenko_tip_deflection,
        reference="Timoshenko beam (bending + shear, Cowper k)",
        quantity="tip deflection -u_z",
        sign=(2, -1.0),  # (component, sign): the compared value is sign * u[component]
        h_calib=0.02,
    ),
    "cylinder": dict(
        geo=geo_cylinder,
        probe=(CYL["a"], 0.0, 0.0),
        exact=lame_bore_displacement,
        reference="Lamé, plane strain",
        quantity="bore radial displacement u_r",
        sign=(0, 1.0),
        h_calib=0.012,
    ),
}


def elastic_case(problem: str, msh: Path, linear: str = "direct") -> str:
    """hencky's case file of an elastic problem of PROBLEMS on the mesh `msh` (in the case's
    folder), with solver.linear `linear`: one step, the probe, the reactions."""
    px, py, pz = PROBLEMS[problem]["probe"]
    head = f"""title: bench {problem} {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
"""
    if problem == "cantilever":
        body = f"""boundary:
  - region: fixed
    displacement: {{x: 0, y: 0, z: 0}}
  - region: tip
    force: [0, 0, {-CANT['P']!r}]
"""
        reactions = "[fixed]"
    else:
        body = cylinder_boundary_yaml(repr(CYL['p']))
        reactions = "[sym_x]"
    return head + body + f"""solver: {{steps: 1, end: 1.0, linear: {linear}}}
output:
  probes:
    - name: probe
      point: [{px!r}, {py!r}, {pz!r}]
  reactions: {reactions}
"""


# ----------------------------------------------------------------------------------------------
# Plastic cylinder (run_plastic_bench.py)
# ----------------------------------------------------------------------------------------------
SY = 240e6  # yield stress, Pa
A_IN, B_OUT = CYL["a"], CYL["b"]


def limit_pressure(sy: float = SY, a: float = A_IN, b: float = B_OUT) -> float:
    return 2 * sy / math.sqrt(3) * math.log(b / a)


class Hill:
    """Elastic-perfectly-plastic thick cylinder, plane strain, with the plastic front at r = c
    (tests/unit/test_verify_plastic.cpp, class Hill): with k = sigma_y/sqrt(3)
    p(c) = k (1 - c^2/b^2 + 2 ln(c/a)), p_L = 2k ln(b/a), u(b) = 2(1 - nu^2) k c^2 / (E b)."""

    def __init__(self, a=A_IN, b=B_OUT, E=E, nu=NU, sy=SY):
        self.a, self.b, self.E, self.nu, self.sy = a, b, E, nu, sy
        self.k = sy / math.sqrt(3)

    def p_of_c(self, c):
        return self.k * (1 - c * c / self.b**2 + 2 * math.log(c / self.a))

    def c_of_p(self, p):
        lo, hi = self.a, self.b
        for _ in range(200):
            m = 0.5 * (lo + hi)
            if self.p_of_c(m) < p:
                lo = m
            else:
                hi = m
        return 0.5 * (lo + hi)

    def u_outer(self, p):
        a, b, nu, E = self.a, self.b, self.nu, self.E
        if p <= self.p_of_c(a):  # elastic (Lamé)
            return p * a * a * 2 * (1 - nu * nu) / (E * (b * b - a * a)) * b
        c = self.c_of_p(p)
        return 2 * (1 - nu * nu) * self.k * c * c / (E * b)


def radial_reference(p_end: float, steps: int, hardening: float = 0.0, n_el: int = 200,
                     a=A_IN, b=B_OUT, E=E, nu=NU, sy=SY, tol=1e-10) -> list[tuple[float, float]]:
    """The cylinder along the radius: u = u(r), strains (du/dr, u/r, 0) (plane strain), von Mises
    with linear isotropic hardening `hardening` (0: perfect), the pressure ramped to p_end in
    `steps` equal increments; n_el quadratic elements (3 Gauss points, weight r dr), radial
    return and Newton with the consistent tangent. Returns (u(a), u(b)) after each increment."""
    H = hardening
    G = E / (2 * (1 + nu))
    K = E / (3 * (1 - 2 * nu))
    D = (K - 2 * G / 3) * np.ones((3, 3)) + 2 * G * np.eye(3)
    one = np.ones(3)
    Idev = np.eye(3) - np.outer(one, one) / 3
    r_nodes = np.linspace(a, b, 2 * n_el + 1)
    n = len(r_nodes)
    gx, gw = np.polynomial.legendre.leggauss(3)
    conn = np.array([[2 * e, 2 * e + 1, 2 * e + 2] for e in range(n_el)])
    N = np.stack([gx * (gx - 1) / 2, 1 - gx**2, gx * (gx + 1) / 2], axis=1)  # (point, node)
    dN = np.stack([gx - 0.5, -2 * gx, gx + 0.5], axis=1)
    xe = r_nodes[conn]
    r_gp = xe @ N.T
    J = xe @ dN.T
    w = gw[None, :] * J * r_gp
    B = np.zeros((n_el, 3, 3, 3))  # (element, point, strain component r/theta/z, node)
    B[:, :, 0, :] = dN[None, :, :] / J[:, :, None]
    B[:, :, 1, :] = N[None, :, :] / r_gp[:, :, None]
    ep = np.zeros((n_el, 3, 3))
    alpha = np.zeros((n_el, 3))
    u = np.zeros(n)
    history = []

    def material(eps):
        s_tr = (eps - ep) @ D.T
        dev = s_tr - s_tr.mean(axis=2, keepdims=True)
        nrm = np.sqrt((dev**2).sum(axis=2))
        q = math.sqrt(1.5) * nrm
        f = q - (sy + H * alpha)
        C = np.broadcast_to(D, eps.shape[:2] + (3, 3)).copy()
        sig, ep_new, al_new = s_tr.copy(), ep.copy(), alpha.copy()
        pl = f > 0
        if pl.any():
            dg = f[pl] / (3 * G + H)
            nh = dev[pl] / nrm[pl][:, None]
            sig[pl] = s_tr[pl] - 2 * G * math.sqrt(1.5) * dg[:, None] * nh
            ep_new[pl] = ep[pl] + math.sqrt(1.5) * dg[:, None] * nh
            al_new[pl] = alpha[pl] + dg
            C[pl] = (K * np.outer(one, one)[None]
                     + (2 * G * (1 - 3 * G * dg / q[pl]))[:, None, None] * Idev[None]
                     + (6 * G * G * (dg / q[pl] - 1 / (3 * G + H)))[:, None, None]
                     * np.einsum("pi,pj->pij", nh, nh))
        return sig, ep_new, al_new, C

    for k in range(1, steps + 1):
        f_ext = np.zeros(n)
        f_ext[0] = p_end * k / steps * a
        for it in range(100):
            eps = np.einsum("egcn,en->egc", B, u[conn])
            sig, ep_new, al_new, C = material(eps)
            fint = np.zeros(n)
            np.add.at(fint, conn, np.einsum("egcn,egc,eg->en", B, sig, w))
            res = f_ext - fint
            if it > 0 and np.linalg.norm(res) <= tol * np.linalg.norm(f_ext):
                break
            Ke = np.einsum("egci,egcd,egdj,eg->eij", B, C, B, w)
            Kg = np.zeros((n, n))
            np.add.at(Kg, (conn[:, :, None], conn[:, None, :]), Ke)
            u = u + np.linalg.solve(Kg, res)
        else:
            raise RuntimeError("1D reference: Newton did not converge")
        ep, alpha = ep_new, al_new
        history.append((float(u[0]), float(u[-1])))
    return history


def geo_slice(h: float, layers: int) -> str:
    """The quarter ring a < r < b meshed in its plane (triangles of size h) and extruded in z by
    `layers` layers of thickness h: a slice layers*h thick whose tetrahedra have about the same
    size in every direction. Refining keeps the slice `layers` elements thick, so the unknowns
    grow as h^-2 and the factorization's fill as that of a 2D mesh. The elastic cylinder's
    geometry and physical groups."""
    return geo_cylinder(h, dict(CYL, Lz=layers * h), layers)


def plastic_problem(layers: int, thickness: float) -> str:
    """The plane-strain slice as a problem of PROBLEMS (for gmsh.size_for's mesh-size fitting
    and mesh cache); returns its name. `layers` > 0: a structured slice `layers` elements thick
    (geo_slice); otherwise an unstructured slice of fixed axial length `thickness` (the elastic
    cylinder's geometry), whose fill grows as that of a 3D mesh."""
    if layers > 0:
        name = f"ring-l{layers}"
        PROBLEMS[name] = dict(geo=lambda h: geo_slice(h, layers), h_calib=0.009)
    else:
        name = f"ring-t{thickness:g}"
        c = dict(CYL, Lz=thickness)
        PROBLEMS[name] = dict(geo=lambda h: geo_cylinder(h, c), h_calib=0.4 * thickness)
    return name


def material_yaml(variant: dict) -> str:
    if variant["hardening"] == 0:
        return f"{{perfect: {{yield: {SY!r}}}}}"
    return f"{{linear: {{yield: {SY!r}, hardening: {variant['hardening']!r}}}}}"


def plastic_case(msh: Path, scheme: str, variant: dict, args) -> str:
    """hencky's case file of the plastic cylinder: `scheme` ("+anderson": with Anderson
    acceleration, "+auto": hencky's default; a plain name is the report's plain iteration,
    `acceleration: none`; "+updated": with `geometry: updated`) on the material `variant`, the
    controls of run_plastic_bench.py's options `args` (steps, tolerance, max_iterations, cutback,
    linear, relaxation(_stiffness), p_end)."""
    label = scheme
    scheme, *tags = scheme.split("+")
    updated = "updated" in tags
    accel = next((t for t in tags if t != "updated"), "")
    solver = [f"scheme: {scheme}", f"steps: {args.steps}", "end: 1.0",
              f"tolerance: {args.tolerance!r}", f"max_iterations: {args.max_iterations}",
              f"cutback: {args.cutback}", f"linear: {args.linear}"]
    if scheme == "initial-strain":
        solver.append(f"relaxation: {args.relaxation}")
    elif scheme == "initial-strain-stiffness":
        solver.append(f"relaxation: {args.relaxation_stiffness}")
    solver.append(f"acceleration: {accel or 'none'}")
    if updated:
        solver.append("geometry: updated")
    return f"""title: plastic bench {label} {variant['name']} {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
    plasticity: {material_yaml(variant)}
{cylinder_boundary_yaml(f'"{args.p_end!r}*t"')}solver: {{{', '.join(solver)}}}
output:
  every: {args.steps}
  probes:
    - name: outer
      point: [{B_OUT!r}, 0.0, 0.0]
    - name: bore
      point: [{A_IN!r}, 0.0, 0.0]
"""


# ----------------------------------------------------------------------------------------------
# Hertz contact (run_contact_bench.py)
# ----------------------------------------------------------------------------------------------
E_STAR = E / (1 - NU * NU)
A = 1e-3            # Hertz contact radius at the full approach, m
R = 100 * A         # sphere radius
DELTA = A * A / R   # full approach (1e-5 m)
R_FINE = 1.2 * A    # the size field is h_c within this distance of the origin
GROWTH = 0.25       # ... and grows by this much per unit distance outside
CAP_EXTENT = 1.6 * A  # the ccx rigid cap covers [-h_c, CAP_EXTENT]^2


class Hertz:
    """Rigid sphere of radius R pressed by an approach d into an elastic half-space (E*)."""

    def __init__(self, R: float = R):
        self.R = R

    def force(self, d):
        return 4.0 / 3.0 * E_STAR * math.sqrt(self.R) * d**1.5

    def radius(self, d):
        return math.sqrt(self.R * d)

    def peak(self, d):
        return 3 * self.force(d) / (2 * math.pi * self.R * d)

    def approach(self, P):
        return (3 * P / (4 * E_STAR * math.sqrt(self.R))) ** (2.0 / 3.0)


def geo_block(hc: float, L: float) -> str:
    """The quarter block [0, L] x [0, L] x [-L, 0] for Gmsh (built-in kernel) with a size field
    h = min(L/4, h_c + GROWTH max(0, |x| - R_FINE)). Physical groups: body; xsym (x = 0), ysym
    (y = 0), top (z = 0), bottom (z = -L); the faces x = L and y = L have none (free)."""
    return f"""// hencky contact benchmark: quarter block L = {L!r}, h_c = {hc!r} within {R_FINE!r} of the origin
L = {L!r};
Point(1) = {{0, 0, 0}}; Point(2) = {{L, 0, 0}}; Point(3) = {{L, L, 0}}; Point(4) = {{0, L, 0}};
Point(5) = {{0, 0, -L}}; Point(6) = {{L, 0, -L}}; Point(7) = {{L, L, -L}}; Point(8) = {{0, L, -L}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Line(5) = {{5, 6}}; Line(6) = {{6, 7}}; Line(7) = {{7, 8}}; Line(8) = {{8, 5}};
Line(9) = {{1, 5}}; Line(10) = {{2, 6}}; Line(11) = {{3, 7}}; Line(12) = {{4, 8}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Curve Loop(2) = {{5, 6, 7, 8}}; Plane Surface(2) = {{2}};
Curve Loop(3) = {{1, 10, -5, -9}}; Plane Surface(3) = {{3}};
Curve Loop(4) = {{2, 11, -6, -10}}; Plane Surface(4) = {{4}};
Curve Loop(5) = {{3, 12, -7, -11}}; Plane Surface(5) = {{5}};
Curve Loop(6) = {{4, 9, -8, -12}}; Plane Surface(6) = {{6}};
Surface Loop(1) = {{1, 2, 3, 4, 5, 6}}; Volume(1) = {{1}};
Physical Volume("body") = {{1}};
Physical Surface("xsym") = {{6}}; Physical Surface("ysym") = {{3}};
Physical Surface("top") = {{1}}; Physical Surface("bottom") = {{2}};
Field[1] = MathEval;
Field[1].F = "min({L / 4!r}, {hc!r} + {GROWTH!r}*max(0, sqrt(x*x + y*y + z*z) - {R_FINE!r}))";
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
"""


def contact_problem(block: float) -> str:
    """The block (L = `block` contact radii) as a problem of PROBLEMS (for gmsh.size_for's
    mesh-size fitting and mesh cache; the mesh parameter h is h_c); returns its name."""
    name = f"hertz-L{block:g}a"
    PROBLEMS[name] = dict(geo=lambda h: geo_block(h, block * A), h_calib=A / 6)
    return name


def contact_case(msh: Path, args) -> str:
    """hencky's case file of the Hertz contact, from run_contact_bench.py's options `args`
    (steps, penetration)."""
    extra = f"\n    penetration: {args.penetration!r}" if args.penetration else ""
    return f"""title: contact bench hertz {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
boundary:
  - region: xsym
    displacement: {{x: 0}}
  - region: ysym
    displacement: {{y: 0}}
  - region: bottom
    displacement: {{x: 0, y: 0, z: 0}}
contact:
  - name: ball
    nodes: top
    surface: {{sphere: {{center: [0, 0, {R!r}], radius: {R!r}}}}}
    motion: [0, 0, "-{DELTA!r}*t"]{extra}
solver: {{steps: {args.steps}, end: 1.0, linear: {getattr(args, "linear", "auto")}}}
output:
  every: {args.steps}
  reactions: [bottom]
"""
