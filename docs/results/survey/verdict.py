import json, statistics, sys
rows = json.load(open(sys.argv[1]))
def am(r): return r["hausdorff_area_mean"]
metrics = [("E_avg", lambda r: r["e_avg"], True), ("E_max", lambda r: r["e_max"], True),
           ("\\|E_sur\\|", lambda r: abs(r["e_sur_signed"]), True), ("Hausdorff (max)", lambda r: r["hausdorff_max"], True),
           ("mean surface distance (area-weighted)", am, True),
           ("median min angle", lambda r: r["median_min_angle_degrees"], False),
           ("share of triangles < 20°", lambda r: r["below_20_degrees"], True)]
def win(a, b, lower):
    if abs(a-b) <= 1e-9*max(abs(a),abs(b)): return "tie"
    return "A" if (a < b) == lower else "B"
out = []
for key, qkey, name in [("gng", "qem", "GNG3D (paper)"), ("gngq", "qem_at_gngq", "GNG3D-Q")]:
    out.append(f"\n**{name} vs QEM at equal vertex count ({len(rows)} runs)**\n")
    out.append(f"| metric | {name} wins | QEM wins | ties | median ratio {name} / QEM |")
    out.append("| --- | ---: | ---: | ---: | ---: |")
    for mname, f, lower in metrics:
        w = [win(f(r[key]), f(r[qkey]), lower) for r in rows]
        ratios = [f(r[key]) / f(r[qkey]) for r in rows if f(r[qkey]) > 0]
        med = statistics.median(ratios) if ratios else float('nan')
        out.append(f"| {mname} | {w.count('A')} | {w.count('B')} | {w.count('tie')} | {med:.3g} |")
    cm = sum(r[key + "_closed_manifold"] for r in rows) if key + "_closed_manifold" in rows[0] else None
    out.append(f"\n{name} output closed and manifold in {cm} of {len(rows)} runs; vertex count equal to the target in "
               f"{sum(r[key]['vertices'] == max(4, int(r['original_vertices'] * r['ratio'] + 0.5)) for r in rows)} of {len(rows)} (target = ratio·|V| rounded half-up, as the survey does); "
               f"GNG seconds total {sum(r[key+'_seconds'] for r in rows):.1f} (QEM {sum(r['qem_seconds'] for r in rows):.1f}).")
print("\n".join(out))
# per-mesh GNG3D-Q/QEM ratios
print("\n| mesh | ratio | vertices | mean dist GNG3D / GNG3D-Q / QEM | Hausdorff GNG3D / GNG3D-Q / QEM | GNG3D-Q/QEM mean | GNG3D-Q/QEM Hausdorff | min angle GNG3D-Q / QEM | GNG3D-Q s |")
print("| --- | ---: | ---: | --- | --- | ---: | ---: | --- | ---: |")
for r in rows:
    g, q, Q = r["gng"], r["gngq"], r["qem_at_gngq"]
    print(f"| {r['mesh']} | {r['ratio']:.2f} | {q['vertices']} | {am(g):.2e} / {am(q):.2e} / {am(Q):.2e} | {g['hausdorff_max']:.2e} / {q['hausdorff_max']:.2e} / {Q['hausdorff_max']:.2e} | {am(q)/am(Q):.2f} | {q['hausdorff_max']/Q['hausdorff_max']:.2f} | {q['median_min_angle_degrees']:.1f}° / {Q['median_min_angle_degrees']:.1f}° | {r['gngq_seconds']:.2f} |")
