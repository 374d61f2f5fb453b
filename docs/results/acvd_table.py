"""Markdown table of docs/results.md's ACVD comparison from the JSON files in docs/results/acvd.

Usage: python3 docs/results/acvd_table.py docs/results/acvd > docs/results/acvd/table.md
(the per-mesh ACVD/GNG3D-Q ratios go to stderr).
"""
import json
import sys

D=sys.argv[1]
rows=[]
def am(h): return (h['forward']['area_mean']+h['backward']['area_mean'])/2
for name,n in [("armadillo",4324),("stanford-bunny",3483),("fandisk",648),("horse",4848)]:
    a=json.load(open(f"{D}/{name}-acvd-metrics.json")); c=json.load(open(f"{D}/{name}-compare.json"))
    g=c['gng']['metrics']; q=c['qem']['metrics']
    def qual(m): s=m['quality']['simplified']; return s['median_min_angle_degrees'], 100*s['below_20_degrees']
    rows.append(f"| {name} | {c['target_vertices']} | {am(a['hausdorff']):.3e} | {am(g['hausdorff']):.3e} | {am(q['hausdorff']):.3e} | {a['hausdorff']['max']:.3e} | {g['hausdorff']['max']:.3e} | {q['hausdorff']['max']:.3e} | {a['e_avg']:.3e} | {g['e_avg']:.3e} | {q['e_avg']:.3e} | {qual(a)[0]:.1f}° / {qual(g)[0]:.1f}° / {qual(q)[0]:.1f}° | {qual(a)[1]:.1f} % / {qual(g)[1]:.1f} % / {qual(q)[1]:.1f} % |")
    print(name, 'mean ratio acvd/gngq', am(a['hausdorff'])/am(g['hausdorff']), 'H gngq<acvd', g['hausdorff']['max']<a['hausdorff']['max'], file=sys.stderr)
print("| mesh (10 %) | vertices | mean dist ACVD | GNG3D-Q | QEM | Hausdorff ACVD | GNG3D-Q | QEM | E_avg ACVD | GNG3D-Q | QEM | median min angle ACVD / GNG3D-Q / QEM | < 20° ACVD / GNG3D-Q / QEM |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
print("\n".join(rows))
