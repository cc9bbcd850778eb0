#!/usr/bin/env python3
"""Run `marsyn solve` on every problem file of a folder, one at a time, and tabulate the results.

For each problem it records whether it verified, the wall time, the search's rounds and its stop
message (result.json `search`, docs/search.md), the stage that failed and the failure. It prints
a Markdown table and "k of N verified", and writes summary.json and summary.md into --out.

    scripts/run_problems.py tests/problems --marsyn build/bin/marsyn --out /tmp/problems-out

Problems run one after the other under `nice -n 5`: the machine is shared, and a second solve in
parallel would distort the wall times. The global ABCD baseline is skipped by default
(--global-budget 0): it is a comparison, not part of the verified result.
"""
import argparse
import json
import pathlib
import subprocess
import sys
import time


def failed_stage(result):
    """The stage of the last failed attempt (plan, track <agent>, certify, verify, ...), or ''."""
    for a in reversed(result.get("attempts", [])):
        outcome = str(a.get("outcome", "")).lower()
        if a.get("stage") != "global ABCD" and not outcome.startswith(("ok", "feasible", "verified", "certified", "controller", "0 violations")):
            return a.get("stage", "")
    return ""


def one_line(text, limit=None):
    text = " ".join(str(text).split())
    return text if limit is None or len(text) <= limit else text[: limit - 3] + "..."


def run_one(path, args, out_root):
    out = out_root / path.stem
    cmd = ["nice", "-n", "5", args.marsyn, "solve", str(path), "--out", str(out),
           "--time-limit", str(args.time_limit), "--runs", str(args.runs),
           "--global-budget", str(args.global_budget)]
    log = out_root / f"{path.stem}.log"
    start = time.monotonic()
    with open(log, "w") as f:
        try:
            # The search may overrun its limit by one round's misjudgement (docs/search.md); past
            # twice the limit plus verification time something is wrong, and the run is killed.
            rc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT,
                                timeout=2 * args.time_limit + 600).returncode
        except subprocess.TimeoutExpired:
            rc = "killed"
    wall = time.monotonic() - start
    row = {"problem": path.name, "exit": rc, "wall_s": round(wall, 2), "log": str(log)}
    result_file = out / "result.json"
    if rc in (0, 1) and result_file.exists():
        r = json.loads(result_file.read_text())
        s = r.get("search", {})
        row.update({
            "verified": r.get("status") == "verified",
            "rounds": len(s.get("rounds", [])),
            "search_time_s": s.get("time_s"),
            "stopped": s.get("stopped", ""),
            "stop_message": s.get("stop_message", ""),
            "tried": s.get("tried", ""),
            "not_tried": s.get("not_tried", []),
            "actions": [x.get("action") for x in s.get("rounds", [])],
            "failed_stage": "" if r.get("status") == "verified" else failed_stage(r),
            "failure": r.get("failure", ""),
            "agents": len(r.get("agents", [])),
            "trackers": sorted({a["tracker"]["name"] for a in r.get("agents", [])}),
            "verification_violations": r.get("verification", {}).get("violations"),
        })
    else:
        tail = log.read_text(errors="replace").strip().splitlines()[-3:]
        row.update({"verified": False, "rounds": None, "stop_message": "", "failed_stage": "no result.json",
                    "failure": one_line(" | ".join(tail), 300)})
    return row


def markdown(rows):
    lines = ["| # | problem | agents | trackers | result | wall s | rounds | failed stage | search's stop message |",
             "|---|---|---|---|---|---|---|---|---|"]
    for i, r in enumerate(rows, 1):
        res = "VERIFIED" if r["verified"] else ("failed" if r["exit"] in (0, 1) else f"exit {r['exit']}")
        lines.append("| {} | {} | {} | {} | {} | {:.1f} | {} | {} | {} |".format(
            i, r["problem"], r.get("agents", ""), ", ".join(r.get("trackers", [])), res, r["wall_s"],
            r["rounds"] if r["rounds"] is not None else "-", r["failed_stage"] or "-",
            one_line(r["stop_message"] or r["failure"]).replace("|", "\\|")))
    k = sum(1 for r in rows if r["verified"])
    lines.append("")
    lines.append(f"**{k} of {len(rows)} verified**")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", type=pathlib.Path, help="folder of problem files (*.yaml)")
    ap.add_argument("--marsyn", default="build/bin/marsyn", help="the marsyn binary (default build/bin/marsyn)")
    ap.add_argument("--time-limit", type=float, default=300, help="the search's budget per problem in seconds (default 300)")
    ap.add_argument("--runs", type=int, default=200, help="closed-loop verification runs per problem (default 200)")
    ap.add_argument("--global-budget", type=float, default=0, help="marsyn's --global-budget (default 0: no global ABCD baseline)")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("run-problems-out"), help="output folder (one sub-folder per problem)")
    ap.add_argument("--only", nargs="*", default=[], help="run only the files whose name contains one of these strings")
    args = ap.parse_args()

    files = sorted(args.folder.glob("*.yaml"))
    if args.only:
        files = [f for f in files if any(s in f.name for s in args.only)]
    if not files:
        sys.exit(f"no *.yaml in {args.folder}")
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for f in files:
        row = run_one(f, args, args.out)
        rows.append(row)
        print(f"{f.name}: {'VERIFIED' if row['verified'] else 'failed'} in {row['wall_s']:.1f} s, "
              f"{row['rounds']} rounds; {one_line(row['stop_message'] or row['failure'], 200)}", flush=True)
        (args.out / "summary.json").write_text(json.dumps(rows, indent=1))
    table = markdown(rows)
    (args.out / "summary.md").write_text(table + "\n")
    print()
    print(table)


if __name__ == "__main__":
    main()
