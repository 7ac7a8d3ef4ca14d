# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Every example under examples/ runs on a coarse mesh (its .geo size parameter is changed in a
# copy), and numbers of its summary.json are checked against the closed-form or reference value
# quoted in the example's README.

# --- Lamé thick cylinder: a = 0.1, b = 0.2, p = 100 MPa, E = 210 GPa, nu = 0.3, plane strain.
#     u_r(a) = (1+nu)/E ((1-2nu) A a + B/a) = 9.0794e-5 m, sigma_theta(a) = A + B/a^2 = 166.67 MPa,
#     sigma_theta(b) = 2A = 66.667 MPa, hoop force on x = 0: p a L = 2e5 N (reaction -x),
#     axial force sigma_z pi (b^2 - a^2)/4 = 2 nu A * 0.0235619 m^2 = 471,238.9 N.
ex_copy lame-cylinder
d="$work/examples/lame-cylinder"
ex_set "$d/cylinder.geo" '^h = [0-9.e-]+;' 'h = 0.02;'
expect "lame-cylinder: runs on a coarse mesh (h = 0.02)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"
ex_check "lame-cylinder: u_r at the bore vs Lame within 1%" "$s" \
  'close(s["probes"]["bore"]["displacement"]["x"], 9.0793650793650794e-05, 0.01)'
ex_check "lame-cylinder: sigma_theta at the bore vs Lame within 2%" "$s" \
  'close(s["probes"]["bore"]["stress"]["yy"], 166.66666666666667e6, 0.02)'
ex_check "lame-cylinder: sigma_theta at the outer surface vs Lame within 2%" "$s" \
  'close(s["probes"]["outer"]["stress"]["yy"], 66.666666666666667e6, 0.02)'
ex_check "lame-cylinder: hoop force (reaction on x = 0) = -p a L to 1e-6" "$s" \
  'close(s["reactions"]["symmetry_x"]["x"], -2.0e5, 1e-6)'
ex_check "lame-cylinder: axial reaction = -2 nu A pi (b^2-a^2)/4 within 0.1%" "$s" \
  'close(s["reactions"]["bottom"]["z"], -471238.89803846896, 1e-3)'
# The run's report (issue 22): the largest von Mises stress is Lame's at the bore,
# sqrt(((sr - st)^2 + (st - sz)^2 + (sz - sr)^2) / 2) with sr = -p, st = 166.67, sz = 2 nu A =
# 20 MPa: 231.33 MPa (a node's extrapolated value: within 3 %), on a node of the bore at t = 1;
# the largest displacement is u_r(a); the pressure's resultant on the quarter bore is p a L along
# x and y, and the reactions balance it.
ex_check "lame-cylinder: report, largest von Mises = Lame's at the bore within 3 %, t = 1" "$s" \
  'close(s["report"]["von_mises"]["value"], ((266.6667e6**2 + 146.6667e6**2 + 120e6**2) / 2) ** 0.5, 0.03) and abs(sum(v * v for v in s["report"]["von_mises"]["position"][:2]) ** 0.5 - 0.1) < 1e-9 and s["report"]["von_mises"]["time"] == 1'
ex_check "lame-cylinder: report, largest displacement = u_r(a) within 1 %, on the bore" "$s" \
  'close(s["report"]["displacement"]["value"], 9.0793650793650794e-05, 0.01) and abs(sum(v * v for v in s["report"]["displacement"]["position"][:2]) ** 0.5 - 0.1) < 1e-9'
ex_check "lame-cylinder: report, loads p a L along x and y, the reactions balance them" "$s" \
  'close(s["report"]["balance"]["loads"][0], 2e5, 1e-9) and close(s["report"]["balance"]["loads"][1], 2e5, 1e-9) and s["report"]["balance"]["imbalance"] < 1e-9 and "equivalent_plastic_strain" not in s["report"]'
expect_cmd "lame-cylinder: plot.py draws the wall's stresses on Lame's, hoop within 3 %" 0 \
  "hoop stress within [0-2]\.[0-9]+ % of Lam" -- env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot.py" "$d/case.out" "$d/wall.png"
if grep -q "^report: balance at t = 1: reactions" "$d/case.out/hencky.log" &&
   grep -q "^report: time (s): .*assembly" "$d/case.out/hencky.log"; then
  ok "lame-cylinder: report, its lines in hencky.log"
else bad "lame-cylinder: report lines missing in hencky.log" "$(grep report "$d/case.out/hencky.log")"; fi

# --- Cantilever: L = 1, 50 x 100 mm, F = 10 kN, E = 210 GPa, nu = 0.3.
#     Timoshenko tip deflection F L^3/(3EI) + F L/(kappa G A) = 3.8387 mm (hencky converges to
#     3.822 mm: the 3D clamp is a little stiffer); top fibre at mid-span M c / I = 60 MPa.
ex_copy cantilever
d="$work/examples/cantilever"
ex_set "$d/beam.geo" '^n = [0-9]+;' 'n = 10;'
expect "cantilever: runs on a coarse mesh (n = 10)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"
ex_check "cantilever: tip deflection vs Timoshenko within 2%" "$s" \
  'close(-s["probes"]["tip"]["displacement"]["z"], 3.8386666666666666e-3, 0.02)'
ex_check "cantilever: mid-span top-fibre stress vs M c / I within 0.5%" "$s" \
  'close(s["probes"]["mid_top"]["stress"]["xx"], 60.0e6, 0.005)'
ex_check "cantilever: clamp reaction balances the 10 kN end load to 1e-6" "$s" \
  'close(s["reactions"]["clamp"]["z"], 1.0e4, 1e-6) and abs(s["reactions"]["clamp"]["x"]) < 1e-2 and abs(s["reactions"]["clamp"]["y"]) < 1e-2'
expect_cmd "cantilever: plot.py draws the deflection along the beam on Timoshenko's" 0 \
  "tip deflection 3\.[0-9]+ mm, Timoshenko 3\.8387 mm \(-[01]\.[0-9]+ %\)" -- \
  env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot.py" "$d/case.out" "$d/along.png"

# --- Thermal plate: edges held in plane, T = 20 + 230 t z/h, E and alpha tables.
#     Top face at t = 1 (250 degC): sigma_xx = -E(250) (alpha(250) 250 - alpha(20) 20)/(1 - nu)
#     = -192.5e9 * 3.035e-3 / 0.7 = -834.625 MPa; at mid-thickness (135 degC) -421.045 MPa;
#     top-face rise (1+nu)/(1-nu) * integral of the thermal strain over z = 5.49119e-5 m.
ex_copy thermal-plate
d="$work/examples/thermal-plate"
ex_set "$d/plate.geo" '^n = [0-9]+;' 'n = 2;'
expect "thermal-plate: runs on a coarse mesh (n = 2)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"
ex_check "thermal-plate: top-face stress vs -E(T) eps_th(T)/(1-nu) within 1%" "$s" \
  'close(s["probes"]["top"]["stress"]["xx"], -834.625e6, 0.01) and close(s["probes"]["top"]["stress"]["yy"], -834.625e6, 0.01)'
ex_check "thermal-plate: mid-thickness stress (135 degC) within 1%" "$s" \
  'close(s["probes"]["middle"]["stress"]["xx"], -421.04539285714286e6, 0.01)'
ex_check "thermal-plate: top-face rise vs the integrated thermal strain within 0.1%" "$s" \
  'close(s["probes"]["top"]["displacement"]["z"], 5.49119461698073e-05, 1e-3)'
ex_check "thermal-plate: probe temperature 250 degC, 4 steps, no table warnings" "$s" \
  'close(s["probes"]["top"]["temperature"], 250.0, 1e-9) and s["steps"] == 4 and s["warnings"] == []'
expect_cmd "thermal-plate: plot.py draws the stress through the thickness on the closed form" 0 \
  "within 0\.[0-9]+ % of the top face" -- env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot.py" "$d/case.out" "$d/through.png"

# --- Bracket: the bolt reactions balance the 1 kN pin load; the tip deflection is within 5% of
#     the fine-mesh value in the README (1.015 mm at h = 5 mm).
ex_copy bracket
d="$work/examples/bracket"
ex_set "$d/bracket.geo" '^h  = [0-9.e-]+;' 'h  = 0.015;'
ex_set "$d/bracket.geo" 'MeshSizeFromCurvature = [0-9]+;' 'MeshSizeFromCurvature = 6;'
expect "bracket: runs on a coarse mesh (h = 15 mm)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"
ex_check "bracket: bolt reactions balance the 1 kN pin load to 1e-6" "$s" \
  'close((r := s["reactions"])["bolt_1"]["x"] + r["bolt_2"]["x"], -1000.0, 1e-6) and abs(r["bolt_1"]["y"] + r["bolt_2"]["y"]) < 1e-3 and abs(r["bolt_1"]["z"] + r["bolt_2"]["z"]) < 1e-3'
ex_check "bracket: tip deflection within 5% of the fine-mesh 1.015 mm" "$s" \
  'close(s["probes"]["tip"]["displacement"]["x"], 1.0154e-3, 0.05)'
ex_check "bracket: converged in 2 steps" "$s" 's["status"] == "converged" and s["steps"] == 2'

# --- Strip with a hole, overload and unload (plasticity). 300 x 100 x 5 mm, hole d = 25 mm,
#     S355 tension-test table, gross stress S = 225 MPa at t = 1 (0.845 of the net-section limit
#     load sigma_y (w - d) t = 133.1 kN), back to 0 at t = 2. Reference values: the README's, at
#     n = 12; here n = 8, whose deviations from them are (measured when this was written) K_t
#     -0.4 %, eps_p at the edge +0.7 %, residual sigma_yy at the edge -1.2 %, eps_p 5 mm into the
#     ligament +1.3 %, permanent set -0.15 %, end displacement at the peak -0.002 %; each
#     tolerance is about three times that. The von Mises stress at the hole edge must be the
#     table's stress at the edge's plastic strain (the point is on the curve; off by the nodal
#     recovery: +0.2 % at n = 8, +0.5 % at n = 6), within 1 %. Exact checks (1e-6): the reaction
#     balances the traction, and the unloading, elastic, retraces the first (elastic) step.
ex_copy plate-hole-overload
d="$work/examples/plate-hole-overload"
ex_set "$d/plate.geo" '^n = [0-9]+;' 'n = 8;'
expect "plate-hole-overload: runs on a coarse mesh (n = 8)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"; hc="$d/case.out/history.csv"
ex_check "plate-hole-overload: converged in the 10 steps given (no cut-back)" "$s" \
  's["status"] == "converged" and s["steps"] == 10 and s["warnings"] == []'
ex_check "plate-hole-overload: reaction on the net section = S W t/2 at the peak to 1e-6" "$hc" \
  'close(at(1.0)["reaction.symmetry_y.y"], -225e6 * 0.05 * 0.0025, 1e-6)'
ex_check "plate-hole-overload: K_t = sigma_yy/S at the hole edge (t = 0.4) vs 3.287 within 1.5%" "$hc" \
  'close(at(0.4)["hole_edge.stress.yy"] / 90e6, 3.287, 0.015)'
ex_check "plate-hole-overload: elastic at t = 0.4, plastic from t = 0.6, elastic unloading" "$hc" \
  'at(0.4)["plastic_points"] == 0 and all(r["plastic_points"] > 0 for r in h if 0.55 < r["time"] <= 1.0) and all(r["plastic_points"] == 0 for r in h if r["time"] > 1.0)'
ex_check "plate-hole-overload: eps_p at the hole edge at the peak vs 4.556e-3 within 2%" "$hc" \
  'close(at(1.0)["hole_edge.equivalent_plastic_strain"], 4.5557e-3, 0.02)'
expect_cmd "plate-hole-overload: plot.py draws the load-elongation and K_t S curves" 0 \
  "K_t = 3\.2[0-9]+, peak 112\.50 kN = 0\.845 P_L" -- env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot.py" "$d/case.out" "$d/le.png"
ex_check "plate-hole-overload: report, the largest eps_p on the hole's edge (x = 12.5 mm), t >= 1" "$s" \
  'abs(s["report"]["equivalent_plastic_strain"]["position"][0] - 0.0125) < 1e-9 and abs(s["report"]["equivalent_plastic_strain"]["position"][1]) < 1e-9 and s["report"]["equivalent_plastic_strain"]["time"] >= 1 and close(s["report"]["equivalent_plastic_strain"]["value"], 4.5557e-3, 0.05)'
ex_check "plate-hole-overload: von Mises at the hole edge = the table's stress at its eps_p within 1%" "$hc" \
  'close(at(1.0)["hole_edge.von_mises"], np.interp(at(1.0)["hole_edge.equivalent_plastic_strain"], [0, 0.0031904762, 0.0080714286, 0.0179047619, 0.0476190476], [355e6, 380e6, 405e6, 440e6, 500e6]), 0.01)'
ex_check "plate-hole-overload: residual sigma_yy at the hole edge vs -365.8 MPa within 3%" "$hc" \
  'close(at(2.0)["hole_edge.stress.yy"], -365.82e6, 0.03)'
ex_check "plate-hole-overload: plastic zone front between 10 and 15 mm; eps_p 5 mm in vs 1.542e-3 within 4%" "$hc" \
  'close(at(1.0)["ligament_5mm.equivalent_plastic_strain"], 1.5422e-3, 0.04) and at(1.0)["ligament_10mm.equivalent_plastic_strain"] > 0 and all(r["ligament_15mm.equivalent_plastic_strain"] == 0 for r in h)'
ex_check "plate-hole-overload: end displacement at the peak vs 1.71290e-4 m within 0.1%" "$hc" \
  'close(at(1.0)["end.displacement.y"], 1.71290e-4, 1e-3)'
ex_check "plate-hole-overload: permanent set vs 2.0995e-6 m within 1%; unloading parallel to the elastic line to 1e-6" "$hc" \
  'close(at(2.0)["end.displacement.y"], 2.0995e-6, 0.01) and close(at(1.0)["end.displacement.y"] - at(2.0)["end.displacement.y"], 2.5 * at(0.4)["end.displacement.y"], 1e-6)'

# --- Ball indentation: rigid ball R = 10 mm pressed 2 um into steel (E = 210 GPa, nu = 0.3).
#     Hertz: P = (4/3) E* sqrt(R) delta^1.5 = 87.0285 N (4 x the quarter model's resultant),
#     p0 = 3P/(2 pi R delta) = 2.07765 GPa, sigma_zz at z = -0.48 a on the axis = -p0/(1 + 0.2304).
ex_copy ball-indentation
d="$work/examples/ball-indentation"
ex_set "$d/block.geo" '^hc = a / [0-9]+;' 'hc = a / 3;'
ex_set "$d/block.geo" '^rf = [0-9.]+ \* a;' 'rf = 1.1 * a;'  # the refined ball: the contact only
expect "ball-indentation: runs on a coarse mesh (hc = a/3)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"; hc="$d/case.out/history.csv"
ex_check "ball-indentation: converged in the 6 steps given, no warnings" "$s" \
  's["status"] == "converged" and s["steps"] == 6 and s["warnings"] == []'
ex_check "ball-indentation: force at full load vs Hertz within 2%" "$hc" \
  'close(-4 * at(1.0)["contact.ball.resultant.z"], 87.028527, 0.02)'
ex_check "ball-indentation: peak contact pressure vs Hertz p0 within 3%" "$hc" \
  'close(at(1.0)["contact.ball.max_pressure"], 2.0776530e9, 0.03)'
ex_check "ball-indentation: sigma_zz at 0.48 a below the centre vs Hertz within 3%" "$hc" \
  'close(at(1.0)["below.stress.zz"], -2.0776530e9 / 1.2304, 0.03)'
ex_check "ball-indentation: the bottom's reaction balances the contact force to 1e-6" "$hc" \
  'all(abs(r["reaction.bottom.z"] + r["contact.ball.resultant.z"]) <= 1e-6 * 87.0 for r in h)'
ex_check "ball-indentation: elastic: the unloading branch retraces the loading one to 1e-6" "$hc" \
  'close(at(1.5)["contact.ball.resultant.z"], at(0.5)["contact.ball.resultant.z"], 1e-6)'
ex_check "ball-indentation: released at t = 2 (at most the touching node left, no force)" "$hc" \
  'at(2.0)["contact.ball.nodes"] <= 1 and abs(at(2.0)["contact.ball.resultant.z"]) < 1e-6 * 87.0'
ex_check "ball-indentation: summary reports the contact (force, nodes, resultant, max_pressure)" "$s" \
  'set(s["contact"]["ball"]) >= {"force", "nodes", "resultant", "max_penetration", "max_pressure"}'
expect_cmd "ball-indentation: plot.py draws the force against Hertz's (a PNG)" 0 "wrote .*P = 8[0-9.]+ N \(Hertz 87.03\)" -- \
  env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot.py" "$d/case.out" "$d/force-approach.png"
if head -c 8 "$d/force-approach.png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a"; then
  ok "ball-indentation: ... the file is a PNG"
else bad "ball-indentation: force-approach.png is not a PNG"; fi
ex_check "ball-indentation: report, the largest contact force is history's, at t = 1" "$s" \
  's["report"]["contact_force"]["ball"]["time"] == 1 and close(s["report"]["contact_force"]["ball"]["value"], max(float(r["contact.ball.force"]) for r in __import__("csv").DictReader(open("'"$hc"'"))), 1e-12)'
ex_check "ball-indentation: history.csv has where the ball is (render.py draws it there)" "$hc" \
  'close(at(1.0)["contact.ball.motion.z"], -2e-6, 1e-12) and at(2.0)["contact.ball.motion.z"] == 0 and all(r["contact.ball.motion.x"] == 0 for r in h)'
ex_check "ball-indentation: summary.json describes the sphere" "$s" \
  's["contact"]["ball"]["surface"] == {"shape": "sphere", "center": [0, 0, 0.01], "radius": 0.01}'
# The same ball past yield (dent.yaml: sigma_y = 600 MPa, H = 2 GPa), on the coarse mesh. Hertz's
# first yield (0.62 p0 = sigma_y, p0 = 1.61 sigma_y) is at an approach of 0.432 um, between the
# steps at 0.4 um (t = 0.2) and 0.6 um (t = 0.3); below it the force is Hertz's.
expect "ball-indentation: dent.yaml (plastic) runs on the coarse mesh, no cut-back" 0 "" -- \
  run "$d/dent.yaml" --quiet
s="$d/dent.out/summary.json"; hd="$d/dent.out/history.csv"
ex_check "ball-indentation, dent: all 18 steps converged, no warnings" "$s" \
  's["status"] == "converged" and s["steps"] == 18 and not s.get("warnings")'
ex_check "ball-indentation, dent: elastic below Hertz's first yield (t = 0.2), plastic above (t = 0.3)" "$hd" \
  'at(0.2)["plastic_points"] == 0 and at(0.3)["plastic_points"] > 0'
ex_check "ball-indentation, dent: force at 0.4 um (elastic) vs Hertz within 2%" "$hd" \
  'close(-4 * at(0.2)["contact.ball.resultant.z"], 87.028527 * 0.2 ** 1.5, 0.02)'
ex_check "ball-indentation, dent: at 2 um the yielded block carries less than Hertz's 87.03 N" "$hd" \
  '-4 * at(1.0)["contact.ball.resultant.z"] < 0.95 * 87.028527'
ex_check "ball-indentation, dent: unloading is elastic (no point yields after t = 1)" "$hd" \
  'all(r["plastic_points"] == 0 for r in h if r["time"] > 1)'
ex_check "ball-indentation, dent: released at t = 2, a dent of more than 0.2 um is left" "$hd" \
  'at(2.0)["contact.ball.nodes"] == 0 and at(2.0)["centre.displacement.z"] < -0.2e-6'
ex_check "ball-indentation, dent: the bottom's reaction balances the contact force to 1e-6" "$hd" \
  'all(abs(r["reaction.bottom.z"] + r["contact.ball.resultant.z"]) <= 1e-6 * 87.0 for r in h)'
expect_cmd "ball-indentation, dent: plot_dent.py draws the force-indentation curve" 0 \
  "wrote .*P = [67][0-9.]+ N \(Hertz elastic 87.03\); dent 0\.[2-9][0-9]* µm" -- \
  env PYTHONPATH="$src/scripts" "$ex_py" "$d/plot_dent.py" "$d/dent.out" "$d/dent-curve.png"

# --- Cantilever hook (geometry: updated): a strip curled by a follower pressure, q L^3/EI = 18 t,
#     against the rod solution of tests/tools/follower_rod.py (tip at t = 1: u_x = -1.2120 L,
#     u_y = -0.7222 L, turned by 141.8 degrees). On the coarse copy (25 elements along, 45
#     steps) measured -1.0 % and +0.45 % at t = 1, -1.1 % and -0.55 % at t = 0.49.
ex_copy cantilever-hook
d="$work/examples/cantilever-hook"
ex_set "$d/strip.geo" '^n = [0-9]+;' 'n = 25;'
ex_set "$d/case.yaml" '^  steps: [0-9]+$' '  steps: 45'
ex_set "$d/case.yaml" '^  every: [0-9]+$' '  every: 45'
expect "cantilever-hook: runs on a coarse mesh (n = 25, 45 steps)" 0 "" -- run "$d/case.yaml" --quiet
hc="$d/case.out/history.csv"
hook_rod='__import__("sys").path.insert(0, "'"$src"'/tests/tools") or True and (fr := __import__("follower_rod"))'
for t in 0.5 1; do
  ex_check "cantilever-hook: the tip at t = $t is the rod's within 2.5 % in x and y" "$hc" \
    "$hook_rod and (r := fr.follower_rod(18 * at($t)['time'])) and close(at($t)['tip.displacement.x'] / 0.25, r[0], 0.025) and close(at($t)['tip.displacement.y'] / 0.25, r[1], 0.025)"
done
if grep -q "cutting back" "$d/case.out/hencky.log"; then
  bad "cantilever-hook: a step was cut back" "$(grep "cutting back" "$d/case.out/hencky.log")"
else
  ok "cantilever-hook: no cut-back"
fi

# --- Weld plate (heat): a Gaussian torch, 750 W into the quarter model (r = 5 mm, 5 mm/s for
#     40 s along the 200 mm weld line), convection and radiation, an hour of cooling; E, alpha
#     and the yield stress over temperature, perfect plasticity, newton. Heat into the quarter:
#     P/4 t_w (1 - r/(L sqrt(pi))) = 29576.858 J, less what backward Euler's steps of 0.5 s miss
#     where the torch's power ramps at the plate's ends, dt^2 P v/(24 r sqrt(pi)) = 17.632 J
#     (Euler-Maclaurin): 29559.226 J. Out: the rows of history.csv, each row's heat flow (top +
#     sides) times its step, plus rho c V (T - 20) still stored at the end (the plate is at
#     20.1 degC everywhere). Measured on the coarse copy (n = 16, 2,540 unknowns): out and stored
#     1.1 J under (4e-5; the Gaussian's quadrature on the coarse mesh), final flow 4e-4 of the
#     peak, von Mises on the weld line 249.9 MPa against the yield stress of 250, sigma_xx there
#     287.5 MPa (the README's 283.7 at n = 24), -78 MPa at the free edge; reactions corner.x
#     1e-12 N, weld_line.y 9e-9 N, mid.z 2e-3 N.
ex_copy weld-plate
d="$work/examples/weld-plate"
ex_set "$d/plate.geo" '^n = [0-9]+;' 'n = 16;'
expect "weld-plate: runs on a coarse mesh (n = 16)" 0 "" -- run "$d/case.yaml" --quiet
s="$d/case.out/summary.json"; hc="$d/case.out/history.csv"
ex_check "weld-plate: converged to t = 3600 s, no warnings (every temperature inside the tables)" "$s" \
  's["status"] == "converged" and s["warnings"] == []'
ex_check "weld-plate: the last row is t = 3600 s, the plate back at 20 degC within 0.2 K" "$hc" \
  'close(h[-1]["time"], 3600.0, 1e-12) and all(abs(h[-1][p + ".temperature"] - 20) < 0.2 for p in ("weld", "edge", "stop"))'
ex_check "weld-plate: heat balance: the torch's heat = the heat that left + the heat still stored, within 2e-4" "$hc" \
  'close(-sum((r["time"] - p["time"]) * (r["heat_flow.top"] + r["heat_flow.sides"]) for p, r in zip([{"time": 0.0}] + h[:-1], h)) + 7850 * 460 * 0.2 * 0.1 * 0.003 * (h[-1]["weld.temperature"] - 20), 750 * 40 * (1 - 0.005 / (0.2 * np.sqrt(np.pi))) - 0.5**2 * 3000 * 0.005 / (24 * 0.005 * np.sqrt(np.pi)), 2e-4)'
ex_check "weld-plate: the heat flows at the end are below 1e-3 of their peak" "$hc" \
  'abs(h[-1]["heat_flow.top"] + h[-1]["heat_flow.sides"]) < 1e-3 * max(abs(r["heat_flow.top"] + r["heat_flow.sides"]) for r in h)'
ex_check "weld-plate: the weld line ends on the yield surface: von Mises = 250 MPa within 1.5%" "$s" \
  'close(s["probes"]["weld"]["von_mises"], 250e6, 0.015)'
ex_check "weld-plate: residual sigma_xx: tension of 1 to 1.2 x yield on the weld line, compression at the edge" "$s" \
  '250e6 < s["probes"]["weld"]["stress"]["xx"] < 300e6 and s["probes"]["edge"]["stress"]["xx"] < -50e6'
ex_check "weld-plate: self-equilibrated: the reactions of the supports vanish (below 1 N)" "$s" \
  'abs(s["reactions"]["corner"]["x"]) < 1 and abs(s["reactions"]["weld_line"]["y"]) < 1 and abs(s["reactions"]["mid"]["z"]) < 1'
