"""The time-limit sweep of docs/notes/anytime.md: every shared mesh at 1, 10 and 50 %, with
--time-limit T for T = the minimum (from the time_limit_below_minimum warning of a 1 us run),
2x the minimum and half the unlimited run's time. Prints one line per run and the summary.

    python3 docs/results/time_limit_sweep.py target/release/gng3d $GNG3D_MESHES
"""
import json, os, subprocess, sys, tempfile

binary, meshes = sys.argv[1], sys.argv[2]
out = os.path.join(tempfile.mkdtemp(), "out.ply")


def run(mesh, ratio, limit=None):
    args = [binary, "simplify", os.path.join(meshes, mesh), out, "--method", "gng",
            "--ratio", ratio, "--json"]
    if limit is not None:
        args += ["--time-limit", repr(limit)]
    return json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)


rows = []
for mesh in sorted(os.listdir(meshes)):
    if mesh in ("igea-1m.ply", "README.md"):
        continue
    for ratio in ["0.01", "0.1", "0.5"]:
        unlimited = run(mesh, ratio)["seconds"]
        fastest = run(mesh, ratio, 1e-6)
        minimum = next(w["minimum_seconds"] for w in fastest["warnings"]
                       if w["kind"] == "time_limit_below_minimum")
        for label, t in [("min", minimum), ("2min", 2 * minimum), ("half", unlimited / 2)]:
            d = run(mesh, ratio, t)
            below = any(w["kind"] == "time_limit_below_minimum" for w in d["warnings"])
            exact = d["vertices"] == d["target_vertices"]
            rows.append((d["seconds"] / t, below, exact))
            print(f"{mesh:22} {ratio:>5} {label:5} T={t:.4f} s took {d['seconds']:.4f} s "
                  f"({d['seconds'] / t:.2f} T) exact={exact} below_minimum={below}", flush=True)
above = [r for r in rows if not r[1]]
print(f"T >= minimum: {sum(r[0] <= 1.05 for r in above)} of {len(above)} within 1.05 T "
      f"(worst {max(r[0] for r in above):.3f} T); exact count in {sum(r[2] for r in rows)} of {len(rows)}")
