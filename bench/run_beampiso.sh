#!/usr/bin/env bash
# Issue 45: hencky against CalculiX on CalculiX's own test deck beampiso.inp (package
# calculix-ccx-test): a 1 x 1 x 8 bar of 32 C3D20R, von Mises with linear isotropic hardening
# (sigma_y = 800, H = 8000, E = 210000, nu = 0.3), the end face z = 8 pulled by 964 N (nodal
# loads that are the consistent ones of a uniform traction), NLGEOM. The deck's first step only
# (its second step unloads). The tip displacement u_z at node 5 (0, 0, 8) for:
#   ccx with NLGEOM at 1, 10 and 100 fixed increments, and without NLGEOM at 1 and 10;
#   hencky with solver.geometry: updated at 1, 10 and 100 steps, and small at 1 and 10;
#   the closed forms of uniaxial tension (the state is homogeneous).
# Writes bench/results/issue45-beampiso.md. Each run takes seconds (ccx at 100 increments ~3 s).
# Usage: bench/run_beampiso.sh [HENCKY_BINARY]     (default build-bench/hencky)
#        BEAMPISO_CCX_FINE=1 bench/run_beampiso.sh ...   adds ccx at 1000 increments (~25 s)
# Needs: calculix-ccx, calculix-ccx-test (bash bench/setup.sh installs both), python3.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
bin="$(realpath "${1:-$src/build-bench/hencky}")"
out="$src/bench/results/issue45-beampiso.md"
[ -x "$bin" ] || { echo "no hencky binary at $bin" >&2; exit 1; }
command -v ccx > /dev/null || { echo "ccx not found: apt-get install calculix-ccx" >&2; exit 1; }
deck="$(dpkg -L calculix-ccx-test 2> /dev/null | grep -E '/beampiso\.inp(\.gz)?$' | head -n 1 || true)"
[ -n "$deck" ] || { echo "beampiso.inp not found: apt-get install calculix-ccx-test" >&2; exit 1; }

work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
cd "$work"
zcat -f "$deck" > beampiso.inp

# --- CalculiX: the deck's model data (everything before the first *STEP) and its first step's
# *CLOAD, with the increments fixed (*STATIC,DIRECT: initial increment = 1/n of the step).
first_step=$(grep -n -i '^\*STEP' beampiso.inp | head -n 1 | cut -d: -f1)
head -n $((first_step - 1)) beampiso.inp > model.inp
awk '{u = toupper($0)} u ~ /^\*STEP/ {s++} s == 1 && u ~ /^\*CLOAD/ {c = 1; print; next}
     c && /^\*/ {exit} c {print}' beampiso.inp > cload.inp
ccx_deck() {  # name nlgeom(0/1) increments
  local inc
  inc=$(python3 -c "print(repr(1.0/$3))")
  {
    cat model.inp
    if [ "$2" = 1 ]; then echo "*STEP,NLGEOM,INC=$(($3 + 10))"; else echo "*STEP,INC=$(($3 + 10))"; fi
    echo "*STATIC,DIRECT"
    echo "$inc,1."
    cat cload.inp
    echo "*NODE PRINT,NSET=GIBO"
    echo "U"
    echo "*EL PRINT,ELSET=EALL"
    echo "S,PEEQ"
    echo "*END STEP"
  } > "$1.inp"
}
ccx_runs="nl:1 nl:10 nl:100 sm:1 sm:10"
[ "${BEAMPISO_CCX_FINE:-0}" = 1 ] && ccx_runs="nl:1 nl:10 nl:100 nl:1000 sm:1 sm:10"
for r in $ccx_runs; do
  kind=${r%%:*}; n=${r##*:}
  ccx_deck "ccx-$kind-$n" "$([ "$kind" = nl ] && echo 1 || echo 0)" "$n"
  t0=$(date +%s.%N)
  ccx -i "ccx-$kind-$n" > "ccx-$kind-$n.log" 2>&1 || true
  echo "$t0 $(date +%s.%N)" > "ccx-$kind-$n.time"
done

# --- hencky: the same mesh, with the supports of *BOUNDARY as node sets and the loaded end as
# an element surface (the faces S2 of elements 29..32 are the end face z = 8).
cp beampiso.inp hk.inp
cat >> hk.inp << 'EOF'
** added for hencky: the supports of *BOUNDARY as node sets, the loaded end as a surface
*NSET,NSET=FIX1
1
*NSET,NSET=FIX2
2
*SURFACE,NAME=TIP,TYPE=ELEMENT
29,S2
30,S2
31,S2
32,S2
EOF
hencky_case() {  # name geometry steps
  cat > "$1.yaml" << EOF
title: beampiso (CalculiX test deck), geometry $2, $3 steps
mesh:
  file: hk.inp
materials:
  - name: HY
    E: 210000
    nu: 0.3
    plasticity: {linear: {yield: 800, hardening: 8000}}
boundary:
  - region: CN7            # the 21 nodes of the face z = 0 (*BOUNDARY CN7,3,3)
    displacement: {z: 0}
  - region: FIX1           # node 1 (0, 0, 0) (*BOUNDARY 1,1,2)
    displacement: {x: 0, y: 0}
  - region: FIX2           # node 2 (1, 0, 0) (*BOUNDARY 2,2,2)
    displacement: {y: 0}
  - region: TIP            # the face z = 8: 964 N in total, a uniform traction
    force: [0, 0, "964*t"]
solver:
  steps: $3
  geometry: $2
output:
  probes:
    - {name: tip, point: [0, 0, 8]}        # node 5
    - {name: centre, point: [0.5, 0.5, 8]} # node 100
  reactions: [CN7]
EOF
}
for r in updated:1 updated:10 updated:100 small:1 small:10; do
  g=${r%%:*}; n=${r##*:}
  hencky_case "hk-$g-$n" "$g" "$n"
  t0=$(date +%s.%N)
  "$bin" run "hk-$g-$n.yaml" --quiet > "hk-$g-$n.log" 2>&1 || true
  echo "$t0 $(date +%s.%N)" > "hk-$g-$n.time"
done

mkdir -p "$(dirname "$out")"
python3 - "$work" "$out" "$bin" "$deck" "$ccx_runs" << 'PY'
import csv, math, os, re, subprocess, sys, datetime
work, out, binary, deck, ccx_runs = sys.argv[1:]
os.chdir(work)
E, nu, sy, H = 210000.0, 0.3, 800.0, 8000.0
L = 8.0

def seconds(name):
    a, b = open(name + '.time').read().split()
    return float(b) - float(a)

def ccx_result(name, n):
    """u_z of node 5 at t = 1 from the .dat, the spread of u_z over the end face, sigma_zz and
    PEEQ of element 1's first point; None if ccx did not reach t = 1 in n increments."""
    try:
        dat = open(name + '.dat').read()
    except OSError:
        return None
    blocks = re.split(r'\n\s*displacements \(vx,vy,vz\) for set GIBO and time\s+', dat)[1:]
    if len(blocks) != n or abs(float(blocks[-1].split()[0]) - 1.0) > 1e-9:
        return None
    uz = {}
    for line in blocks[-1].splitlines()[1:]:
        f = line.split()
        if len(f) == 4 and f[0].isdigit():
            uz[int(f[0])] = float(f[3])
        elif uz and not f:
            continue
        elif uz:
            break
    stress = re.findall(r'stresses \(elem, integ\.pnt\.,sxx,syy,szz,sxy,sxz,syz\) for set EALL and time\s+(\S+)\s*\n\s*\n\s*1\s+1\s+(\S+)\s+(\S+)\s+(\S+)', dat)
    peeq = re.findall(r'equivalent plastic strain \(elem, integ\.pnt\.,pe\)for set EALL and time\s+(\S+)\s*\n\s*\n\s*1\s+1\s+(\S+)', dat)
    lat = [float(l.split()[1]) for l in blocks[-1].splitlines()[1:] if l.split()[:1] == ['6']]
    return dict(u=uz[5], spread=max(uz.values()) - min(uz.values()),
                szz=float(stress[-1][3]) if stress else float('nan'),
                peeq=float(peeq[-1][1]) if peeq else float('nan'),
                ux6=lat[0] if lat else float('nan'))

def hencky_result(name):
    try:
        rows = list(csv.DictReader(open(name + '.out/history.csv')))
    except OSError:
        return None
    last = rows[-1] if rows else None
    if last is None or abs(float(last['time']) - 1.0) > 1e-9:
        return None
    log = open(name + '.out/hencky.log').read()
    m = re.search(r'converged in \S+ s \((\d+) steps, (\d+) iterations\)', log)
    return dict(u=float(last['tip.displacement.z']), all_iterations=int(m.group(2)) if m else -1,
                spread=abs(float(last['tip.displacement.z']) - float(last['centre.displacement.z'])),
                increments=len(rows), iterations=sum(int(r['iterations']) for r in rows),
                cutbacks=log.count('cutting back'),
                szz=float(last['tip.stress.zz']), peeq=float(last['tip.equivalent_plastic_strain']),
                ezz=float(last['tip.strain.zz']), eezz=float(last['tip.elastic_strain.zz']),
                ux_centre=float(last['centre.displacement.x']))

def neo_hooke_elastic(sigma):
    """ccx's elastic law (Simo 1988: tau = K/2 (J^2 - 1) 1 + mu dev(b_e bar)) under uniaxial Cauchy
    stress sigma: the axial logarithmic elastic strain, by Newton on the two principal stretches."""
    mu, K = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))
    def res(a, b):
        la, lb = math.exp(a), math.exp(b); J = la * lb * lb
        d = mu * J ** (-2.0 / 3.0) * (la * la - lb * lb)
        return (K / 2 * (J * J - 1) - d / 3, d - J * sigma)
    x = [sigma / E, -nu * sigma / E]
    for _ in range(30):
        r = res(*x); h = 1e-9
        c0 = [(res(x[0] + h, x[1])[i] - r[i]) / h for i in range(2)]
        c1 = [(res(x[0], x[1] + h)[i] - r[i]) / h for i in range(2)]
        det = c0[0] * c1[1] - c1[0] * c0[1]
        x = [x[0] - (c1[1] * r[0] - c1[0] * r[1]) / det, x[1] - (-c0[1] * r[0] + c0[0] * r[1]) / det]
    return x[0]

def bisect(g, a, b):
    for _ in range(200):
        m = 0.5 * (a + b)
        if g(a) * g(m) <= 0: b = m
        else: a = m
    return 0.5 * (a + b)

cload = [l.split(',') for l in open('cload.inp') if not l.startswith('*') and l.strip()]
sets = {}
name = None
for line in open('beampiso.inp'):
    m = re.match(r'\*NSET\s*,\s*NSET\s*=\s*(\w+)', line, re.I)
    if m: name = m.group(1).upper(); sets[name] = []; continue
    if line.startswith('*'): name = None; continue
    if name: sets[name] += [int(x) for x in line.replace(',', ' ').split()]
F = sum(len(sets.get(c[0].strip().upper(), [0])) * float(c[2]) for c in cload)
F0 = 964.0
# Closed forms of uniaxial tension under a dead load F on the initial area 1 (the state is
# homogeneous): the Kirchhoff stress is tau = J sigma = lambda F.
#  (a) Hencky's: logarithmic elastic strain tau = E ln(V_e), yield on tau (hencky updated):
#      ln lambda = tau/E + (tau - sy)/H
lam_a = bisect(lambda l: math.log(l) - F0 * l / E - (F0 * l - sy) / H, 1.0, 1.2)
#  (b) the same with the hardening curve read as Cauchy stress (sigma = tau/J, J = exp((1-2nu)tau/E)),
#      as ccx's incplas reads *PLASTIC under NLGEOM:
def gb(l):
    tau = F0 * l; J = math.exp((1 - 2 * nu) * tau / E)
    return math.log(l) - tau / E - (tau / J - sy) / H
lam_b = bisect(gb, 1.0, 1.2)
#  (c) small strain: F/E + (F - sy)/H
u_small = L * (F0 / E + (F0 - sy) / H)

rows = []
for r in ccx_runs.split():
    kind, n = r.split(':'); n = int(n)
    res = ccx_result('ccx-%s-%d' % (kind, n), n)
    rows.append(('CalculiX 2.20 (C3D20R, 2×2×2 points)', 'NLGEOM' if kind == 'nl' else 'linear', str(n), res,
                 seconds('ccx-%s-%d' % (kind, n))))
for g, n in (('updated', 1), ('updated', 10), ('updated', 100), ('small', 1), ('small', 10)):
    res = hencky_result('hk-%s-%d' % (g, n))
    inc = str(n) if res is None or res['increments'] == n else '%d (taken: %d, %d cut-backs)' % (n, res['increments'], res['cutbacks'])
    rows.append(('hencky (hex20, 3×3×3 points)', '`%s`' % g, inc, res, seconds('hk-%s-%d' % (g, n))))
ref = [r for r in rows if r[0].startswith('hencky') and r[1] == '`updated`' and r[2] == '100'][0][3]
uref = ref['u'] if ref else float('nan')

def rel(u):
    if uref != uref: return '–'
    d = 100 * (u / uref - 1)
    return '0.00 %' if abs(d) < 0.005 else '%+.2f %%' % d

ver = subprocess.run([binary, '--version'], capture_output=True, text=True).stdout.strip()
ccxver = subprocess.run(['dpkg-query', '-W', '-f=${Version}', 'calculix-ccx'], capture_output=True, text=True).stdout
now = datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')
o = []
o.append('# Issue 45: beampiso.inp, hencky against CalculiX under large deformation\n')
o.append('Run %s by `bench/run_beampiso.sh` with %s (`%s`) and calculix-ccx %s; the deck is `%s`.\n'
         % (now, ver, binary, ccxver, deck))
o.append('A 1 × 1 × 8 bar of 2 × 2 × 8 = 32 C3D20R, von Mises with linear isotropic hardening '
         '(σ_y = 800, plastic modulus 8000: `*PLASTIC` 800, 0 / 1600, 0.1), E = 210000, ν = 0.3, '
         'the end face z = 8 pulled by %.5f N in total (the deck\'s first step; its second unloads). '
         'u_z(tip) is node 5 at (0, 0, 8); every node of the end face has the same u_z '
         '(the largest spread over the face is given below): the state is homogeneous uniaxial '
         'tension, so the closed forms at the end of the table are exact for each model.\n' % F)
o.append('| code | geometry | increments | u_z(tip) | vs hencky updated, 100 steps | wall time (s) |')
o.append('|---|---|---|---:|---:|---:|')
spread = 0.0
for code, geo, inc, res, sec in rows:
    if res is None:
        o.append('| %s | %s | %s | did not reach t = 1 | – | %.2f |' % (code, geo, inc, sec))
        continue
    spread = max(spread, res['spread'])
    o.append('| %s | %s | %s | %.5f | %s | %.2f |' % (code, geo, inc, res['u'], rel(res['u']), sec))
o.append('| closed form: Hencky strain, hardening on the Kirchhoff stress (hencky\'s model) | large | – | %.5f | %s | – |'
         % (L * (lam_a - 1), rel(L * (lam_a - 1))))
o.append('| closed form: Hencky strain, hardening on the Cauchy stress (ccx\'s reading of `*PLASTIC`) | large | – | %.5f | %s | – |'
         % (L * (lam_b - 1), rel(L * (lam_b - 1))))
o.append('| closed form: small strain | small | – | %.5f | %s | – |' % (u_small, rel(u_small)))
o.append('')
o.append('Largest difference of u_z between the nodes of the end face in any run: %.1e.\n' % spread)

hk = {(r[1], r[2].split()[0]): r[3] for r in rows if r[0].startswith('hencky')}
cx = {(r[1], r[2]): r[3] for r in rows if r[0].startswith('CalculiX')}
upd = [hk.get(('`updated`', s)) for s in ('1', '10', '100')]
o.append('## Notes\n')
if all(upd):
    us = [u['u'] for u in upd]
    o.append('- **hencky `updated` does not depend on the step count**: %s at 1, 10 and 100 steps '
             '(largest difference %.1e), the closed form of its model to %.1e. '
             % (', '.join('%.7f' % u for u in us), max(us) - min(us), abs(us[-1] - L * (lam_a - 1))))
    if upd[0]['increments'] != 1:
        o.append('  `steps: 1` is not run as one increment, though: newton\'s matrix turned indefinite in the '
                 'second iteration of the whole-load step ("pivot ... failed"), and the step was cut back to '
                 '%d increments (%d iterations, %d of them in the increments kept). ccx takes the whole load in one '
                 'increment (%d iterations).'
                 % (upd[0]['increments'], upd[0]['all_iterations'], upd[0]['iterations'],
                    len(re.findall(r'^ iteration \d+', open('ccx-nl-1.log').read(), re.M))))
    h = upd[-1]
    J = (1 + h['u'] / L) * (1 + h['ux_centre'] / 0.5) ** 2
    o.append('- hencky\'s hardening acts on the Kirchhoff stress τ = Jσ: at t = 1, σ_zz = %.3f (the Cauchy '
             'stress, 964/A), ε^p = %.6f, and σ_y + 8000 ε^p = %.3f = Jσ_zz with J = %.6f. '
             'ln λ = %.7f (from u_z) = τ/E + ε^p; the written `strain.zz` is %.7f and `elastic_strain.zz` %.7f = σ_zz/E, '
             'not τ/E: the written elastic strain is the Cauchy stress over E, %.1e short of the logarithmic strain.'
             % (h['szz'], h['peeq'], sy + H * h['peeq'], J, math.log(1 + h['u'] / L), h['ezz'], h['eezz'],
                math.log(1 + h['u'] / L) - h['ezz']))
c1, c10, c100 = cx.get(('NLGEOM', '1')), cx.get(('NLGEOM', '10')), cx.get(('NLGEOM', '100'))
if c1 and c10 and c100:
    fine = cx.get(('NLGEOM', '1000'))
    o.append('- **ccx with NLGEOM depends on the increments**: %.5f, %.5f, %.5f at 1, 10, 100%s. Its '
             'plasticity (incplas.f) is Simo\'s 1988 multiplicative model: a neo-Hookean-like elastic part on the '
             'isochoric elastic left Cauchy–Green tensor, an additive return on it, and its stress–strain '
             'curve read as Cauchy stress (multiplied by J to give the Kirchhoff yield stress). The update is '
             'first order in the increment: the answer moves by %.1f %% between 1 and %s increments, towards a limit '
             'below hencky\'s (next note).'
             % (c1['u'], c10['u'], c100['u'], (', %.5f at 1000' % fine['u']) if fine else '',
                100 * ((fine or c100)['u'] / c1['u'] - 1), '1000' if fine else '100'))
    c = fine or c100
    lam = 1 + c['u'] / L
    o.append('- What is left between the codes at many increments: (1) the curve is Kirchhoff in hencky, '
             'Cauchy in ccx: the closed form with a Cauchy curve is %.5f, %.2f %% below hencky\'s (ccx: PEEQ '
             '%.6f, σ_y + 8000 PEEQ = %.3f against its σ_zz %.3f); (2) ccx\'s ln λ − PEEQ = %.6f, the elastic '
             'part of its stretch, is smaller than the %.6f its own neo-Hookean law gives at that stress '
             '(Hencky\'s: σJ/E = %.6f): the two elastic laws differ by %.0e at an elastic strain of 0.5 %%, which does '
             'not matter; the difference, %.1e (of the order of ε_e·ε^p), is in how its additive update on the elastic '
             'Cauchy–Green tensor counts plastic strain, and was not traced further.'
             % (L * (lam_b - 1), 100 * (L * (lam_b - 1) / uref - 1), c['peeq'], sy + H * c['peeq'], c['szz'],
                math.log(lam) - c['peeq'], neo_hooke_elastic(c['szz']),
                c['szz'] * math.exp((1 - 2 * nu) * c['szz'] / E) / E,
                c['szz'] * math.exp((1 - 2 * nu) * c['szz'] / E) / E - neo_hooke_elastic(c['szz']),
                neo_hooke_elastic(c['szz']) - (math.log(lam) - c['peeq'])))
o.append('- Both codes read the same mesh and the same supports: ccx\'s `*BOUNDARY` CN7 (the 21 nodes of z = 0) '
         'in z, node 1 in x and y, node 2 in y; hencky: the NSETs CN7, FIX1 = {1}, FIX2 = {2} (the last two '
         'added to hencky\'s copy of the deck). The load: the deck\'s `*CLOAD` on the 21 nodes of the end face '
         '(corners of the 2 × 2 quadratic faces −F/48, −F/24, −F/12 by the number of faces they belong to, '
         'mid-side nodes F/12, F/6) is exactly the consistent load of a uniform traction F/A (the figures are '
         'rounded to 7 digits: they add up to %.5f); hencky\'s `force: [0, 0, 964 t]` on the surface TIP '
         '(faces S2 of elements 29–32) integrates the traction 964/A₀ with the face\'s shape functions, the '
         'same nodal forces. Both are dead loads (fixed direction and size).' % F)
o.append('- Integration: ccx C3D20R has 2 × 2 × 2 points (reduced), hencky reads C3D20R as its 20-node '
         'hexahedron with 3 × 3 × 3 points (it warns). The state is homogeneous, so this changes nothing here.')
o.append('- Without NLGEOM ccx and `geometry: small` agree with the small-strain closed form '
         '8 (964/E + 164/8000) = %.5f.' % u_small)
o.append('\n## The case (geometry: updated, 100 steps)\n')
o.append('```yaml\n' + open('hk-updated-100.yaml').read() + '```')
open(out, 'w').write('\n'.join(o) + '\n')
print('\n'.join(o))
PY
