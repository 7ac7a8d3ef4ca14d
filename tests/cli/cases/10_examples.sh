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
