#!/usr/bin/env python3
"""The verification's share of `marsyn solve` on problem files (issue 24's "<= 20% of solve").

For each problem: `marsyn solve` (wall time per stage from result.json), then, on the controllers
that solve wrote, `marsyn verify` with the same binary and, when --baseline is given, with another
one (say main's build), alternating, so that both verify the very same controllers in the same
minutes. Prints a Markdown table and writes it with the raw figures to --out/verify_share.{md,json}.

    scripts/verify_share.py examples/multi_drone.yaml examples/formation.yaml \\
        --marsyn build/bin/marsyn --baseline /tmp/main/bin/marsyn --out /tmp/share

"same" says whether the two binaries' verify printed the same margins, runs and counts (every
line but the timings); the verify columns are CPU seconds (user) and wall seconds of the
whole command (loading the controllers included) and the closed-loop runs' own wall time.
"""
import argparse
import json
import pathlib
import resource
import subprocess
import sys
import time


def run(cmd):
    """Runs cmd; returns (stdout, wall s, user CPU s of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - t0
    user = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
    if p.returncode not in (0, 1):
        sys.exit(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stderr[-2000:]}")
    return p.stdout, wall, user


def verify(binary, problem, folder, runs):
    out, wall, user = run([binary, "verify", str(problem), "--controllers", str(folder), "--runs", str(runs)])
    runs_s = None
    for line in out.splitlines():
        if line.startswith("time"):  # "time          3.018 s, closed-loop runs 3.007 s (...)"
            runs_s = float(line.split("closed-loop runs")[1].split()[0])
    result = [l for l in out.splitlines() if not l.startswith(("time", "check", "integrator"))]
    return {"wall_s": wall, "user_s": user, "runs_s": runs_s, "result": result}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("problems", nargs="+", type=pathlib.Path)
    ap.add_argument("--marsyn", default="build/bin/marsyn")
    ap.add_argument("--baseline", help="another marsyn binary to verify the same controllers with")
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--out", type=pathlib.Path, required=True)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for problem in args.problems:
        folder = args.out / problem.stem
        _, solve_wall, _ = run([args.marsyn, "solve", str(problem), "--out", str(folder), "--runs", str(args.runs),
                                "--global-budget", "0"])
        r = json.loads((folder / "result.json").read_text())
        v = r.get("verification", {})
        row = {
            "problem": problem.stem, "status": r.get("status"), "solve_wall_s": solve_wall,
            "total_s": r.get("total_time_s"), "plan_s": r.get("plan", {}).get("time_s"),
            "track_s": r.get("tracking_time_s"), "certify_s": r.get("certification", {}).get("time_s"),
            "verify_s": v.get("time_s"),
        }
        row["share"] = row["verify_s"] / row["total_s"] if row["verify_s"] and row["total_s"] else None
        row["verify"] = verify(args.marsyn, problem, folder, args.runs)
        if args.baseline:
            row["baseline"] = verify(args.baseline, problem, folder, args.runs)
            row["same"] = row["baseline"]["result"] == row["verify"]["result"]
        rows.append(row)
        print(f"{problem.stem}: {row['status']}, verification {row['verify_s']:.2f} of {row['total_s']:.2f} s", file=sys.stderr)

    def f(x, d=2):
        return "-" if x is None else f"{x:.{d}f}"

    head = "| problem | status | solve s | plan s | track s | certify s | verification s | share |"
    sep = "|---|---|---|---|---|---|---|---|"
    if args.baseline:
        head += " verify CPU / wall s (this) | verify CPU / wall s (baseline) | same |"
        sep += "---|---|---|"
    lines = [head, sep]
    for r in rows:
        line = (f"| {r['problem']} | {r['status']} | {f(r['total_s'])} | {f(r['plan_s'])} | {f(r['track_s'])} | "
                f"{f(r['certify_s'])} | {f(r['verify_s'])} | {f(100 * r['share'], 0) if r['share'] is not None else '-'}% |")
        if args.baseline:
            a, b = r["verify"], r["baseline"]
            line += f" {f(a['user_s'])} / {f(a['wall_s'])} | {f(b['user_s'])} / {f(b['wall_s'])} | {'yes' if r['same'] else 'NO'} |"
        lines.append(line)
    text = "\n".join(lines) + "\n"
    print(text)
    (args.out / "verify_share.md").write_text(text)
    (args.out / "verify_share.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
