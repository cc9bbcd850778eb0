#!/usr/bin/env python3
"""The unicycle field at growing sizes (issue 50's scale table): for each N, `marsyn check`'s
predicted memory per stage, then `marsyn solve` in one process (2 threads) and over MPI ranks (1
thread each, as many ranks as cores here), each stage's time and what it added to memory
(result.json `memory`, rank 0's) and the largest process's peak (ru_maxrss of the run and its
children). Writes a Markdown table and two SVG plots (time and peak memory against N).

    python3 scripts/field_scale.py --marsyn build/bin/marsyn --sizes 25 100 400 1000 --ranks 1 2 \\
        --out /tmp/field-scale --md docs/benchmarks-field.md --svg docs/field-scale

Nothing else should run on the machine meanwhile: the times are wall times.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from svg_lines import line_plot  # noqa: E402

UNITS = {"bytes": 1, "KiB": 2 ** 10, "MiB": 2 ** 20, "GiB": 2 ** 30, "TiB": 2 ** 40}
# What each stage's prediction is called in `check`'s memory lines.
PREDICTED = {"plan": "planning", "tracking": "tracking", "verification": "verification"}


def measured(cmd, log):
    """Runs cmd in a fresh Python so that ru_maxrss covers this run alone; (rc, wall s, peak bytes)."""
    probe = ("import resource, subprocess, sys, time\n"
             "t = time.time()\n"
             "with open(sys.argv[1], 'w') as f:\n"
             "    rc = subprocess.run(sys.argv[2:], stdout=f, stderr=subprocess.STDOUT).returncode\n"
             "print(rc, time.time() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024)\n")
    out = subprocess.run([sys.executable, "-c", probe, log] + [str(c) for c in cmd], capture_output=True, text=True,
                         check=True).stdout.split()
    return int(out[0]), float(out[1]), float(out[2])


def check_predictions(marsyn, problem, log):
    """Each stage's figure from `marsyn check` (bytes), by the names result.json uses."""
    rc, _, _ = measured([marsyn, "check", problem], log)
    text = open(log).read()
    if rc != 0:
        sys.exit(f"check failed on {problem}:\n{text}")
    out = {}
    for line in text.splitlines():
        words = line.replace("memory", " ", 1).split() if line.startswith("memory") else line.split()
        for stage, word in PREDICTED.items():
            # "planning about 46.4 MiB", "tracking at most about 43.1 MiB"
            if words[:1] == [word] and "about" in words[1:4]:
                at = words.index("about")
                out[stage] = float(words[at + 1]) * UNITS[words[at + 2].rstrip(",")]
    return out


def mb(b):
    return "-" if b is None else f"{b / 1e6:.0f}" if b >= 1e7 else f"{b / 1e6:.1f}"


def s(x):
    return "-" if x is None else f"{x:.0f}" if x >= 100 else f"{x:.1f}" if x >= 1 else f"{x:.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--marsyn", default=os.path.join(HERE, "..", "build", "bin", "marsyn"))
    ap.add_argument("--sizes", type=int, nargs="+", default=[25, 100, 400, 1000])
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--time-limit", type=float, default=900)
    ap.add_argument("--out", default="/tmp/field-scale")
    ap.add_argument("--md", help="write the table here (default: print it)")
    ap.add_argument("--svg", help="prefix of the two plots: PREFIX-time.svg, PREFIX-memory.svg")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    mpirun = shutil.which("mpirun")
    started = time.time()
    rows, series_t, series_m = [], {}, {}
    for n in a.sizes:
        problem = os.path.join(a.out, f"field{n}.yaml")
        subprocess.run([sys.executable, os.path.join(HERE, "unicycle_field.py"), str(n), "--seed", str(a.seed), "--out",
                        problem], check=True, capture_output=True)
        pred = check_predictions(a.marsyn, problem, os.path.join(a.out, f"check{n}.txt"))
        for ranks in a.ranks:
            if ranks > 1 and not mpirun:
                print(f"field {n}: no mpirun, {ranks} ranks skipped", file=sys.stderr)
                continue
            out = os.path.join(a.out, f"field{n}-r{ranks}")
            shutil.rmtree(out, ignore_errors=True)
            solve = [a.marsyn, "solve", problem, "--out", out, "--time-limit", a.time_limit]
            cmd = solve + ["--threads", 2] if ranks == 1 else \
                [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", ranks] + solve + ["--threads", 1]
            t0 = time.time()
            rc, wall, peak = measured(cmd, out + ".log")
            try:
                res = json.load(open(os.path.join(out, "result.json")))
            except (OSError, ValueError):
                res = {}
            srch, ver, mem = res.get("search", {}), res.get("verification", {}), res.get("memory", {})
            status = res.get("status", f"exit {rc}")
            added = {k: (mem.get(k) or {}).get("added_bytes") for k in PREDICTED}
            print(f"field {n}, {ranks} rank(s): {status}, {wall:.1f} s, peak {peak / 1e6:.0f} MB "
                  f"({time.time() - t0:.0f} s)", file=sys.stderr)
            rows.append([n, ranks, status.upper() if status in ("verified", "failed", "stopped") else status,
                         s(srch.get("plan_time_s")), s(srch.get("track_time_s")), s(srch.get("certify_time_s")),
                         s(ver.get("time_s")), s(ver.get("runs")) if ver.get("runs") else "-", s(wall), mb(peak)] +
                        [f"{mb(added[k])} / {mb(pred.get(k))}" for k in PREDICTED])
            with open(out + ".run.json", "w") as f:
                json.dump({"robots": n, "ranks": ranks, "rc": rc, "wall_s": wall, "peak_bytes": peak, "predicted": pred}, f)
            series_t.setdefault(ranks, []).append((n, wall))
            series_m.setdefault(ranks, []).append((n, peak / 1e6))
    write_outputs(a, rows, series_t, series_m, started)


def page(a, table, plots):
    """The Markdown page: what ran, where, the command, the table and the plots."""
    def out(*cmd):
        try:
            return subprocess.run(cmd, capture_output=True, text=True, cwd=os.path.join(HERE, "..")).stdout.strip()
        except OSError:
            return ""
    commit = out("git", "rev-parse", "--short", "HEAD")
    dirty = " with uncommitted changes" if out("git", "status", "--porcelain", "--untracked-files=no") else ""
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    mem = next((int(l.split()[1]) * 1024 for l in open("/proc/meminfo") if l.startswith("MemTotal:")), 0)
    cmd = (f"python3 scripts/field_scale.py --sizes {' '.join(map(str, a.sizes))} --ranks "
           f"{' '.join(map(str, a.ranks))} --seed {a.seed} --time-limit {a.time_limit:g}")
    lines = ["# The unicycle field at scale", "",
             f"Generated by scripts/field_scale.py at commit {commit}{dirty}, {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} "
             f"(UTC), on {cpu}, {os.cpu_count()} cores, {mem / 2 ** 30:.1f} GiB. Do not edit by hand: run it again.", "",
             "```sh", cmd + "   # then: --md docs/benchmarks-field.md --svg docs/field-scale", "```", "",
             "N unicycles 2 m apart, shuffled within blocks of 5 x 5 among pillars (`scripts/unicycle_field.py N "
             f"--seed {a.seed}`, T = 123), everything left to marsyn (`tracker: auto`, auto eps). One process runs "
             "`marsyn solve` with two threads; MPI runs `mpirun -np R marsyn solve ... --threads 1` (one thread per "
             "rank, as many ranks as cores here). Times are wall seconds from result.json (stage times) and around "
             "the command (total); the peak is the largest process's resident set (ru_maxrss); the stage columns "
             "give what each stage added to rank 0's process at its peak beside `marsyn check`'s prediction "
             "(tracking's is an upper figure for one process; over MPI, rank 0 also holds the other ranks' controller "
             "files while it reads them, docs/mpi.md). Teams above 100 agents get 100,000 agent runs spread over the team "
             "(`runs`, at least 200; the certificate is the guarantee, the runs can only refute).", "",
             table, ""]
    lines += [f"![{t}]({os.path.basename(p)})" for t, p in plots]
    return "\n".join(lines) + "\n"


def write_outputs(a, rows, series_t, series_m, started):
    head = ["robots", "ranks", "result", "plan s", "track s", "certify s", "verify s", "runs", "total s",
            "peak MB (largest process)", "plan MB added / predicted", "tracking MB", "verification MB"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    text = "\n".join(lines) + "\n"
    plots = []
    if a.svg:
        colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
        label = {1: "one process, 2 threads"}
        for suffix, series, ylabel in (("time", series_t, "marsyn solve, wall s"),
                                       ("memory", series_m, "peak MB of the largest process")):
            path = f"{a.svg}-{suffix}.svg"
            line_plot(path, [(label.get(r, f"{r} MPI ranks, 1 thread each"), colours[i % 4], pts)
                             for i, (r, pts) in enumerate(sorted(series.items()))], "robots", ylabel)
            plots.append((ylabel + " against robots", path))
    if a.md:
        with open(a.md, "w") as f:
            f.write(page(a, text, plots))
    else:
        print(text)
    print(f"all runs: {time.time() - started:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
