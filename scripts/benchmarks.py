#!/usr/bin/env python3
"""Measures marsyn on this machine and writes docs/benchmarks.md from scratch (issue 53 item 4).

Every figure of docs/benchmarks.md comes from one run of this script; the file says the commit,
the date, the machine and the build it was measured on, and prints above each table the shell
command that reproduces its figures. What it measures, one marsyn process at a time:

  a. end to end: `marsyn solve` on every problem in examples/*.yaml (1000 verification runs, the
     default): wall time, peak memory, the stages' times, rounds, trackers, guarantee;
  b. GAMARA's tracker beside marsyn's: each example with every agent's tracker forced to `abcd`
     (the paper's local ABCD; its automatic grid where the file gives none) and to `funnel`;
  c. the planners (`marsyn bench --stage plan --no-track`);
  d. large teams: the unicycle field (scripts/unicycle_field.py) of 25, 100, 400 robots (1000 with
     --large): `marsyn check`'s memory, `marsyn solve` per stage;
  e. exported controllers: `marsyn export --format c`, compiled with `cc -Os` where a compiler is
     at hand;
  f. beside the paper's Table 2 (the paper's figures are constants below, with their source);
  g. how the figures moved: a short hand-kept table of earlier figures (constants below, from the
     diary this file replaced) beside this run's.

    python3 scripts/benchmarks.py                      # everything but 1000 robots: about 40 min on 2 cores
    python3 scripts/benchmarks.py --quick --out /tmp/b.md   # a few examples, a small field: 2-3 min
    python3 scripts/benchmarks.py --large              # also the field of 1000 robots
    python3 scripts/benchmarks.py --force-tracker abcd examples/bicycles.yaml   # the copy table b solves

Progress goes to stderr, one line per run with its time. A run that fails, is refused or passes
its time limit is a row that says so; the script goes on. Run it on an otherwise idle machine:
marsyn uses two threads (its default), and a second job on a 2-core machine doubles its times.
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import textwrap
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
LIMIT_LINES = 400
LOADS = []  # the 1-minute load average as each run started
UNITS = {"bytes": 1, "KiB": 1024, "MiB": 1024 ** 2, "GiB": 1024 ** 3, "TiB": 1024 ** 4}

# The paper's Table 2 (Majumdar, Mallik, Salamati, Soudjani, Zareian, "Symbolic Reach-Avoid Control
# of Multi-Agent Systems", as printed in its Table 2).
# Planning on a 4-core i5-4590 (16 GB); local ABCD on the same machine except the crane's (48-core
# Xeon, 1.5 TB); global ABCD ran out of 1.5 TB in every case. Seconds; N_l: state-input pairs of
# the largest agent's abstraction; N_g: of the global abstraction.
PAPER_TABLE2 = [
    # example, label, T_plan, N_l, T_abs, T_syn, N_g
    ("multi_drone", "multi-drone (10)", "77.85", 1.13e8, "30.75", "6.66", 2.70e110),
    ("crane_vehicle", "crane + vehicle", "0.65", 8.56e8, "511.24", "91.43", 2.16e18),
    ("lane_merging", "lane merging (6)", "89.02", 1.07e8, "22.79", "5.29", 1.69e59),
    ("formation", "formation (5)", "114.34", 1.55e8, "39.46", "7.83", 3.65e50),
]

# How the figures moved: earlier figures, as docs/benchmarks.md's diary gave them (the diary's last
# version: `git show f9b6c78:docs/benchmarks.md`, section named in the third field). The fifth
# field says which of this run's figures is the same thing, or None.
HISTORY = [
    # what, then, where and when, key of this run's figure
    ("multi_drone `solve`, total", "2.1 s (sampled guarantee); 13.2 s (continuous, load 4-6)",
     "2026-11-22 \"End to end\"; issue 10 \"Continuous time vs sampled\"", "solve:multi_drone:total"),
    ("crane_vehicle `solve`, total (the crane's tracker: abcd then, funnel since 2026-12-02)", "25.7 s (abcd crane, sampled); 78.2 s (abcd, continuous, load 2.8)",
     "2026-11-22 \"End to end\"; 2026-12-01 \"Funnel vs abcd\"", "solve:crane_vehicle:total"),
    ("crane's abcd tracking (all-abcd crane_vehicle)", "56.1 s idle; 77.4 s at load 2.8",
     "2026-11-22 \"Tracking\"; 2026-12-01 \"Funnel vs abcd\"", "abcd:crane_vehicle:track"),
    ("crane_vehicle_swing `solve`, total", "70.1 s; 100.5 s",
     "2026-11-22 \"End to end\"; 2026-12-04 session 20", "solve:crane_vehicle_swing:total"),
    ("pendulum / lane_merging / formation `solve`", "0.8 / 1.5 / 1.6 s (sampled)",
     "2026-11-22 \"End to end\"", "solve:pendulum,lane_merging,formation:total"),
    ("1000 runs of the ten drones (verification)", "8.38 s (load 4-7); 1.37 s; 0.56 s; 0.37 s",
     "2026-12-02 broad phase, four runs at once; 2026-12-04 sessions 16, 17", "solve:multi_drone:verify"),
    ("multi_drone plan stage", "0.149 s (sampled); 0.11 s (continuous)",
     "2026-11-22; 2026-12-04 session 21", "solve:multi_drone:plan"),
    ("field of 100 robots `solve`", "15.9-16.6 s before, 15.0-15.6 s after the screened projection",
     "2026-12-06 \"Large teams\" (f9b6c78)", "field:100:total"),
    ("plan memory predicted by `marsyn check`, fields of 25 / 100 / 400 / 1000", "20 / 49 / 431 / 2486 MB "
     "(measured plan peaks 27 / 63 / 413 / 2167 MB)", "2026-12-06 \"Large teams\"", "field:pred"),
    ("field of 1000 robots", "refused by the loader (core's dense figure 14.4 GiB); accepted at "
     "2.49 GB (altro's own figure), no plan in 319 s", "2026-12-06 \"Large teams\" (19dca34, f9b6c78)", "field:1000:status"),
    ("global ABCD of global_baseline.yaml", "346 s, 2.36e8 pairs", "2026-11-22 \"The global ABCD baseline\"",
     "global:time"),
    ("one drone's abcd controller (`marsyn track`)", "0.19-0.20 s, 22 MB (the reference code: 54.9 s, 8.0 GB)",
     "2026-11-22 \"Tracking\"", "track:drone1:abcd"),
    ("crane's abcd controller exported to C (dense)", "10.5 MB of tables (10,548,105 B)", "2026-12-01 \"Exported controllers\" (b9a7007)",
     "export:crane-abcd"),
]

DEFAULT_QUICK_EXAMPLES = ["pendulum", "crane_vehicle", "multi_drone", "bicycles"]
PLANNER_EXAMPLES = ["pendulum", "crane_vehicle", "multi_drone"]
EXPORT_ROWS = [  # (example, agent, which solve: "solve" = as shipped, "abcd" = table b's abcd run)
    ("pendulum", "pendulum", "solve"),
    ("multi_drone", "drone1", "solve"),
    ("crane_vehicle", "vehicle", "solve"),
    ("crane_vehicle", "crane", "solve"),
    ("crane_vehicle", "crane", "abcd"),
    ("bicycles", "east", "solve"),
]


def log(msg):
    print(f"[benchmarks {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Formatting


def sig(x, digits=3):
    """x to 3 significant digits, plain where that reads well (0.0123, 12.3, 1230), else 1.23e+08."""
    if x is None:
        return "-"
    x = float(x)
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        s = f"{x:.{digits}g}"
        if "e" in s:  # 1.23e+03 -> 1230
            s = f"{x:.0f}"
        return s
    return f"{x:.{digits - 1}e}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def mb(kb):
    """ru_maxrss (KiB) in MB (1e6 bytes, as every size in the file)."""
    return "-" if kb is None else sig(kb * 1024 / 1e6)


def size_text(n):
    if n is None:
        return "-"
    for unit, f in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= f:
            return f"{sig(n / f)} {unit}"
    return f"{int(n)} B"


def rel(p):
    """A path as the commands show it: relative to the repository where it lies inside."""
    p = pathlib.Path(p).resolve()
    try:
        return str(p.relative_to(ROOT))
    except ValueError:
        return str(p)


def one_line(text, words=12):
    w = " ".join(str(text).split()).split(" ")
    return " ".join(w[:words]) + (" ..." if len(w) > words else "")


def cell(text):
    return str(text).replace("|", "/").replace("\n", " ")


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(cell(c) if c not in (None, "") else "-" for c in r) + " |")
    return out


def wrap(lines, width=100):
    """Paragraphs and list items wrapped at `width` (tables, headings and code blocks as they are)."""
    out, in_code = [], False
    for line in lines:
        if line.startswith("```"):
            in_code = not in_code
        if in_code or line.startswith(("```", "|", "#")) or len(line) <= width:
            out.append(line)
        elif line.startswith("- "):
            out += textwrap.wrap(line, width, subsequent_indent="  ", break_on_hyphens=False, break_long_words=False)
        else:
            out += textwrap.wrap(line, width, break_on_hyphens=False, break_long_words=False)
    return out


def code(lines):
    return ["```sh"] + list(lines) + ["```"]


# ---------------------------------------------------------------------------------------------
# Running marsyn


def run(cmd, timeout=None, grace=60, cwd=ROOT):
    """Runs one command in its own process (no shell): wall seconds, peak resident set (KB, the
    figure /usr/bin/time -f %M prints: ru_maxrss of wait4), exit code, stderr. After `timeout`
    seconds it sends SIGTERM (marsyn then stops at the next agent or round and writes what it
    has), after `grace` more SIGKILL."""
    LOADS.append(loadavg())
    start = time.monotonic()
    with tempfile.TemporaryFile() as err, tempfile.TemporaryFile() as out:
        p = subprocess.Popen([str(c) for c in cmd], stdout=out, stderr=err, cwd=cwd)
        killed = None
        deadline = None if timeout is None else start + timeout
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            now = time.monotonic()
            if deadline is not None and now > deadline:
                if killed is None:
                    p.send_signal(signal.SIGTERM)
                    killed = "SIGTERM"
                    deadline = now + grace
                else:
                    p.kill()
                    killed = "SIGKILL"
                    deadline = None
            time.sleep(0.05)
        p.returncode = os.waitstatus_to_exitcode(status)
        wall = time.monotonic() - start
        err.seek(0)
        out.seek(0)
        return {"rc": p.returncode, "wall": wall, "peak_kb": ru.ru_maxrss, "killed": killed,
                "stderr": err.read().decode(errors="replace"), "stdout": out.read().decode(errors="replace")}


def error_reason(r):
    """The first error line of a failed run, without its file:line:column location."""
    for line in r["stderr"].splitlines() + r["stdout"].splitlines():
        if line.startswith("error:"):
            line = line[len("error:"):].strip()
            line = re.sub(r"^\S+:\d+:\d+:\s*", "", line)
            return line
    tail = [l for l in r["stderr"].splitlines() if l.strip()]
    return tail[-1] if tail else f"exit code {r['rc']}"


def read_json(path):
    try:
        return json.loads(pathlib.Path(path).read_text())
    except (OSError, ValueError):
        return None


def solve(marsyn, problem, out, args, extra=(), timeout=None):
    """`marsyn solve` into `out`; returns run figures and result.json (or None)."""
    shutil.rmtree(out, ignore_errors=True)
    cmd = [marsyn, "solve", problem, "--out", out] + list(extra)
    limit = timeout if timeout is not None else args.time_limit
    # The limit is the search's; the verification runs after it, and a round may overrun it
    # (docs/search.md): past twice the limit plus ten minutes something is wrong.
    r = run(cmd, timeout=2 * limit + 600)
    r["result"] = read_json(pathlib.Path(out) / "result.json")
    r["status"] = status_of(r)
    log(f"solve {rel(problem)} {' '.join(map(str, extra))}: {r['status']}, {r['wall']:.1f} s wall, "
        f"{r['peak_kb'] / 1024:.0f} MB")
    return r


def status_of(r):
    res = r.get("result")
    if r["killed"] == "SIGKILL":
        return f"killed after {r['wall']:.0f} s"
    if r["killed"] == "SIGTERM" and res is None:
        return f"stopped by SIGTERM, no result.json ({r['wall']:.0f} s)"
    if res is None:
        return "refused: " + one_line(error_reason(r), 10) if r["rc"] == 2 else "FAILED: " + one_line(error_reason(r), 10)
    st = str(res.get("status", "?")).upper()
    if st == "VERIFIED":
        return st
    why = str(res.get("search", {}).get("stopped") or res.get("failure") or "")
    agents = res.get("agents", [])
    bad = [a for a in agents if a.get("tracker", {}).get("status") != "controller"]
    m = re.search(r"the time limit \((\S+ s)\) was reached (in|before) round (\d+)", why)
    if m:
        why = f"time limit {m.group(1)} {m.group(2)} round {m.group(3)}"
        if bad:
            why += f", {len(bad)} of {len(agents)} agents without controller"
    elif bad and why.startswith("no controller"):
        msg = re.sub(r"^agent \S+: ", "", str(bad[0].get("tracker", {}).get("message", "")))
        why = f"no controller for {len(bad)} of {len(agents)} agents ({bad[0].get('name')}: {one_line(msg, 7)})"
    else:
        why = one_line(why, 10)
    return st + (": " + why if why else "")


def stage_times(res):
    s = (res or {}).get("search", {})
    v = (res or {}).get("verification", {})
    return (s.get("plan_time_s"), s.get("track_time_s"), s.get("certify_time_s"),
            v.get("time_s") if v.get("ran", True) else None, (res or {}).get("total_time_s"))


def tracker_counts(res):
    counts = {}
    for a in (res or {}).get("agents", []):
        t = a.get("tracker", {})
        name = t.get("name", "?")
        if t.get("status") not in (None, "controller"):
            name += " (" + str(t.get("status")) + ")"
        counts[name] = counts.get(name, 0) + 1
    return ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "-"


def ctrl_bytes(out):
    files = list(pathlib.Path(out).glob("*.ctrl"))
    return sum(f.stat().st_size for f in files) if files else None


# ---------------------------------------------------------------------------------------------
# The problems and the forced-tracker copies


def is_problem(path):
    """A problem file has top-level `agents:` (or `name:` and `tau:`); others are skipped."""
    text = pathlib.Path(path).read_text()
    return re.search(r"^agents\s*:", text, re.M) is not None and re.search(r"^tau\s*:", text, re.M) is not None


def value_end(line, start):
    """End index of a YAML flow value starting at `start` (balanced braces, or up to ',' '}' '#')."""
    i, depth = start, 0
    while i < len(line):
        c = line[i]
        if c == "{":
            depth += 1
        elif c == "}":
            if depth == 0:
                return i
            depth -= 1
            if depth == 0:
                return i + 1
        elif c in ",#" and depth == 0:
            return i
        i += 1
    return i


def names_tracker(value, tracker):
    v = value.strip()
    return v == tracker or re.match(r"\{\s*name\s*:\s*" + re.escape(tracker) + r"\s*[,}]", v) is not None


def force_tracker(text, tracker):
    """The problem text with every agent's tracker set to `tracker`: each `tracker:` value that
    does not already name it (a name or `{name: ..., params: ...}`; one kept that names it keeps
    its parameters) becomes the name, and a top-level `tracker:` is added when the file has none.
    For abcd, a file without any `eta_x` gets `eta_x: auto` and `eta_u: auto` in `defaults` (abcd's
    automatic grid, docs/parameters.md): without a grid abcd refuses every agent."""
    lines = text.split("\n")
    out, top_level, skip_indent = [], False, None
    for line in lines:
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if skip_indent is not None:  # the body of a block-style `tracker:` mapping
            if stripped and not stripped.startswith("#") and indent > skip_indent:
                continue
            skip_indent = None
        if stripped.startswith("#"):
            out.append(line)
            continue
        m = re.match(r"^(\s*(?:-\s+)?)tracker\s*:\s*(.*)$", line)
        if m:
            value = m.group(2)
            body = value.split("#")[0].strip()
            if m.group(1) == "":
                top_level = True
            if body == "":  # block mapping below
                skip_indent = len(m.group(1))
                out.append(f"{m.group(1)}tracker: {tracker}")
                continue
            if not names_tracker(body, tracker):
                out.append(f"{m.group(1)}tracker: {tracker}")
            else:
                out.append(line)
            continue
        # `tracker:` inside a flow mapping, e.g. `- {name: a, tracker: funnel, ...}`
        pos, new = 0, ""
        for fm in re.finditer(r"([{,]\s*)tracker\s*:\s*", line):
            if fm.start() < pos:
                continue
            vs = fm.end()
            ve = value_end(line, vs)
            value = line[vs:ve]
            new += line[pos:vs] + (value if names_tracker(value, tracker) else tracker)
            pos = ve
        out.append(new + line[pos:])
    if not top_level:
        # after the top-level `name:` line (block style files start with their scalars)
        for i, line in enumerate(out):
            if re.match(r"^name\s*:", line):
                out.insert(i + 1, f"tracker: {tracker}")
                break
        else:
            out.insert(0, f"tracker: {tracker}")
    if tracker == "abcd" and not re.search(r"\beta_x\s*:", text):
        for i, line in enumerate(out):
            if re.match(r"^defaults\s*:\s*(#.*)?$", line):
                out.insert(i + 1, "  eta_x: auto   # abcd's automatic grid (added by scripts/benchmarks.py)")
                out.insert(i + 2, "  eta_u: auto")
                break
            m = re.match(r"^defaults\s*:\s*\{(.*)\}\s*(#.*)?$", line)
            if m:
                out[i] = "defaults: {eta_x: auto, eta_u: auto, " + m.group(1) + "}"
                break
        else:
            out.append("defaults: {eta_x: auto, eta_u: auto}")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# The header: commit, machine, build


def git(*a):
    try:
        return subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def machine():
    cpu = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    if not cpu:
        cpu = platform.processor() or platform.machine()
    mem = None
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal:"):
                mem = int(line.split()[1]) * 1024
    except OSError:
        pass
    osname = platform.system()
    try:
        for line in open("/etc/os-release"):
            if line.startswith("PRETTY_NAME="):
                osname = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    flags = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("flags"):
                f = line.split()
                flags = ", ".join(x for x in ("avx2", "fma", "avx512f") if x in f)
                break
    except OSError:
        pass
    return cpu, os.cpu_count(), mem, osname, flags


def build_info(marsyn):
    cache = None
    for c in (pathlib.Path(marsyn).resolve().parent.parent / "CMakeCache.txt", ROOT / "build" / "CMakeCache.txt"):
        if c.exists():
            cache = c
            break
    btype, flags = "?", ""
    if cache:
        text = cache.read_text(errors="replace")
        m = re.search(r"^CMAKE_BUILD_TYPE:STRING=(.*)$", text, re.M)
        btype = m.group(1) if m else "?"
        m = re.search(r"^CMAKE_CXX_FLAGS_" + btype.upper() + r":STRING=(.*)$", text, re.M)
        flags = m.group(1) if m else ""
    cxx = ""
    try:
        cxx = subprocess.run(["c++", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        pass
    version = subprocess.run([marsyn, "--version"], capture_output=True, text=True).stdout.split("\n")
    built = datetime.datetime.fromtimestamp(pathlib.Path(marsyn).stat().st_mtime).strftime("%Y-%m-%d %H:%M")
    return btype, flags, cxx, ", ".join(l.strip() for l in version if l.strip()), built


def loadavg():
    try:
        return open("/proc/loadavg").read().split()[0]
    except OSError:
        return "?"


# ---------------------------------------------------------------------------------------------
# The tables


class Bench:
    def __init__(self, args):
        self.a = args
        self.m = args.marsyn
        self.mshow = rel(args.marsyn)
        self.work = pathlib.Path(args.work)
        self.now = {}  # this run's figures by key, for the history table
        self.solves = {}  # example -> run of table a
        self.forced = {}  # (example, tracker) -> run of table b

    # a. End to end
    def end_to_end(self, examples, skipped):
        out_root = self.work / "solve"
        rows = []
        for ex in examples:
            r = solve(self.m, ex, out_root / ex.stem, self.a)
            self.solves[ex.stem] = r
            res = r["result"]
            plan, track, certify, verify, total = stage_times(res)
            rounds = len(res.get("search", {}).get("rounds", [])) if res else None
            n_agents = len(res.get("agents", [])) if res else None
            rows.append([f"`{ex.stem}`", n_agents, r["status"], sig(r["wall"]), mb(r["peak_kb"]), sig(plan),
                         sig(track), sig(verify), rounds, tracker_counts(res),
                         (res or {}).get("guarantee", "-")])
            self.now[f"solve:{ex.stem}:total"] = r["wall"]
            self.now[f"solve:{ex.stem}:verify"] = verify
            self.now[f"solve:{ex.stem}:plan"] = plan
        L = ["## End to end: `marsyn solve`", "",
             "Every problem in `examples/`, solved as shipped (its own trackers and planner, the default 1000 "
             "closed-loop verification runs, two threads). Wall time and peak memory are the whole command's; "
             "the stage times (s) are result.json's `search.plan_time_s`, `search.track_time_s` and "
             "`verification.time_s`; \"rounds\" counts the search's rounds (docs/search.md); \"trackers\" the "
             "agents per tracker.", ""]
        L += code([f"for f in examples/*.yaml; do",
                   f"  /usr/bin/time -f \"%e s %M KB\" {self.mshow} solve $f --out {self.work}/solve/$(basename $f .yaml)",
                   f"done   # figures: the folder's result.json"])
        L.append("")
        L += table(["example", "agents", "status", "wall s", "peak MB", "plan s", "track s", "verify s",
                    "rounds", "trackers", "guarantee"], rows)
        if skipped:
            L += ["", "Skipped (not problem files): " + ", ".join(f"`{rel(s)}`" for s in skipped) + "."]
        gb = self.solves.get("global_baseline")
        if gb and gb["result"]:
            g = gb["result"].get("global_abcd", {})
            L += ["", f"`global_baseline.yaml`'s global ABCD (one abstraction of the product over the whole domain, "
                  f"{sig(g.get('state_input_pairs'))} state-input pairs, about {size_text(g.get('memory_bytes_estimate'))}): "
                  f"{g.get('status', '-')}"
                  + (f", {sig(g.get('time_s'))} s" if g.get("time_s") else "")
                  + ("" if self.a.global_baseline else
                     "; `python3 scripts/benchmarks.py --global` adds a run with the budget raised (about 25 min)") + "."]
        return L

    # a'. The global baseline with its global abstraction
    def global_baseline(self):
        ex = ROOT / "examples" / "global_baseline.yaml"
        out = self.work / "global"
        budget = self.a.global_budget
        r = solve(self.m, ex, out, self.a, extra=["--global-budget", f"{budget:g}"])
        res = r["result"] or {}
        g = res.get("global_abcd", {})
        loc = [a.get("tracker", {}) for a in res.get("agents", [])]
        self.now["global:time"] = g.get("time_s") if g.get("time_s") else None
        L = ["### The global ABCD baseline", "",
             "`examples/global_baseline.yaml` (two double integrators on crossing lines) is small enough for one "
             "abstraction of the product over the whole domain, the comparison the paper could not run (OOM). Its "
             "estimate is above the default budget of 2e9 bytes, so the command raises it:", ""]
        L += code([f"/usr/bin/time -f \"%e s %M KB\" {self.mshow} solve examples/global_baseline.yaml "
                   f"--global-budget {budget:g} --out {out}"])
        L.append("")
        rows = [["decentralized (per agent, abcd)",
                 " and ".join(sig(t.get("state_input_pairs")) for t in loc) or "-",
                 " and ".join(sig((t.get("abstraction_time_s") or 0) + (t.get("synthesis_time_s") or 0)) for t in loc) or "-",
                 r["status"]],
                ["global (product, whole domain)", sig(g.get("state_input_pairs")), sig(g.get("time_s")),
                 g.get("status", "-")]]
        L += table(["", "state-input pairs", "abstraction + synthesis s", "result"], rows)
        L += ["", f"The whole command: {sig(r['wall'])} s wall, {mb(r['peak_kb'])} MB peak."]
        return L

    # b. Trackers side by side
    def trackers(self, examples):
        rows = []
        tmp = self.work / "trackers"
        tmp.mkdir(parents=True, exist_ok=True)
        for ex in examples:
            row = [f"`{ex.stem}`"]
            for t in ("abcd", "funnel"):
                copy = tmp / f"{ex.stem}-{t}.yaml"
                copy.write_text(force_tracker(ex.read_text(), t))
                r = solve(self.m, copy, tmp / f"{ex.stem}-{t}", self.a,
                          extra=["--global-budget", "0", "--time-limit", f"{self.a.compare_limit:g}"],
                          timeout=self.a.compare_limit)
                r["example"] = ex.stem
                self.forced[(ex.stem, t)] = r
                res = r["result"]
                _, track, _, _, _ = stage_times(res)
                status = r["status"]
                size = ctrl_bytes(tmp / f"{ex.stem}-{t}") if res else None
                row += [status, sig(track) if res else "-", sig(r["wall"]), mb(r["peak_kb"]), size_text(size)]
                if res:
                    self.now[f"{t}:{ex.stem}:track"] = track
            rows.append(row)
        L = ["## GAMARA's tracker beside the funnel", "",
             "The same problems with every agent's tracker forced to `abcd` (GAMARA's local ABCD: a grid abstraction "
             "of the tube and a reachability game per agent, the paper's method) and to `funnel` (marsyn's LQR "
             "feedback verified with zonotopes, docs/funnel.md). A file without a grid gets abcd's automatic one "
             "(`eta_x: auto`, `eta_u: auto` in `defaults`). \"track s\" is the tracking stage over every round, "
             "\"total s\" and \"peak MB\" the whole command's, \"controllers\" the `.ctrl` files' bytes (all agents). "
             f"Each search is limited to {self.a.compare_limit:g} s (`--time-limit`; a round in progress finishes "
             "first, docs/search.md); the global baseline is skipped (`--global-budget 0`).", ""]
        L += code([f"python3 scripts/benchmarks.py --force-tracker abcd examples/X.yaml > {tmp}/X-abcd.yaml   # and funnel",
                   f"/usr/bin/time -f \"%e s %M KB\" {self.mshow} solve {tmp}/X-abcd.yaml --global-budget 0 "
                   f"--time-limit {self.a.compare_limit:g} --out {tmp}/X-abcd"])
        L.append("")
        L += table(["example", "abcd", "track s", "total s", "peak MB", "controllers",
                    "funnel", "track s", "total s", "peak MB", "controllers"], rows)
        L += [""] + self.one_agent()
        return L

    def one_agent(self):
        """`marsyn track` of one drone on the solve's plan, each tracker: the whole command."""
        plan = self.work / "solve" / "multi_drone" / "plan.json"
        tmp = self.work / "trackers"
        if not plan.exists():
            return []
        rows = []
        for t in ("abcd", "funnel"):
            copy = tmp / f"multi_drone-{t}.yaml"
            if not copy.exists():
                continue
            out = tmp / f"track-drone1-{t}"
            shutil.rmtree(out, ignore_errors=True)
            r = run([self.m, "track", copy, "--agent", "drone1", "--plan", plan, "--out", out], timeout=600)
            ok = r["rc"] == 0 and (out / "drone1.ctrl").exists()
            log(f"track drone1 ({t}): exit {r['rc']}, {r['wall']:.2f} s, {r['peak_kb'] / 1024:.0f} MB")
            rows.append([t, "controller" if ok else "FAILED: " + one_line(error_reason(r), 8), sig(r["wall"]),
                         mb(r["peak_kb"]), size_text((out / "drone1.ctrl").stat().st_size) if ok else "-"])
            if ok:
                self.now[f"track:drone1:{t}"] = f"{sig(r['wall'])} s, {mb(r['peak_kb'])} MB"
        if not rows:
            return []
        L = ["One agent alone, the paper's unit of local ABCD (one drone of `multi_drone.yaml` on the solve's plan; "
             "the whole command's wall time and peak memory):", ""]
        L += code([f"{self.mshow} track {tmp}/multi_drone-abcd.yaml --agent drone1 --plan {plan} --out {tmp}/track-drone1-abcd"
                   "   # and -funnel"])
        L.append("")
        L += table(["tracker", "result", "wall s", "peak MB", "`.ctrl`"], rows)
        return L

    # f. Beside the paper's Table 2
    def paper(self):
        rows = []
        for ex, label, t_plan, n_l, t_abs, t_syn, n_g in PAPER_TABLE2:
            r = self.forced.get((ex, "abcd"))
            res = r["result"] if r else None
            if not res:
                rows.append([label, t_plan, "not run", sig(n_l), "-", f"{t_abs} + {t_syn}", "-", sig(n_g), "-"])
                continue
            plan = res.get("search", {}).get("plan_time_s")
            agents = [a.get("tracker", {}) for a in res.get("agents", []) if a.get("tracker", {}).get("name") == "abcd"]
            big = max(agents, key=lambda t: t.get("state_input_pairs") or 0) if agents else {}
            ng = res.get("global_abcd", {}).get("state_input_pairs") or None
            plan_text = sig(plan) + ("" if res.get("status") == "verified" else f" ({res.get('status')})")
            rows.append([label, t_plan, plan_text, sig(n_l), sig(big.get("state_input_pairs")),
                         f"{t_abs} + {t_syn}",
                         f"{sig(big.get('abstraction_time_s'))} + {sig(big.get('synthesis_time_s'))}", sig(n_g), sig(ng)])
        L = ["## Beside the paper's Table 2", "",
             "The paper's figures (Table 2 of Majumdar et al., *Symbolic Reach-Avoid Control of Multi-Agent Systems*: "
             "planning and local ABCD on a 4-core i5-4590, the crane's ABCD on a 48-core Xeon with 1.5 TB; global ABCD "
             "ran out of memory in every case) beside marsyn's all-`abcd` runs of the table above (two cores). "
             "N_l is the largest agent's abstraction (tube cells x steps x inputs), abs + syn its abstraction and "
             "synthesis time (marsyn's `abstraction_time_s`, `synthesis_time_s` of that agent); N_g the product grid "
             "over the whole domain, which marsyn estimates and skips. The examples depart from the paper where each "
             "file says (eps, bounds, goals), which moves N_l and N_g somewhat; marsyn's plans also satisfy the "
             "specification between the samples (continuous-time guarantee), the paper's at the samples.", ""]
        t = self.work / "trackers"
        L += code([f"python3 scripts/benchmarks.py --force-tracker abcd examples/crane_vehicle.yaml > {t}/crane_vehicle-abcd.yaml",
                   f"{self.mshow} solve {t}/crane_vehicle-abcd.yaml --global-budget 0 --time-limit {self.a.compare_limit:g} "
                   f"--out {t}/crane_vehicle-abcd   # result.json: search.plan_time_s, agents[].tracker"])
        L.append("")
        L += table(["case", "plan s (paper)", "plan s (marsyn)", "N_l (paper)", "N_l (marsyn)", "abs + syn s (paper)",
                    "abs + syn s (marsyn)", "N_g (paper)", "N_g (marsyn)"], rows)
        return L

    # c. Planners
    def planners(self, examples):
        out = self.work / "planners"
        shutil.rmtree(out, ignore_errors=True)
        cmd = [self.m, "bench", "--stage", "plan", "--no-track", "--examples", ",".join(examples), "--out", out]
        r = run(cmd, timeout=self.a.time_limit * len(examples) * 4 + 120)
        log(f"bench --stage plan {','.join(examples)}: exit {r['rc']}, {r['wall']:.1f} s")
        rows = []
        csv = out / "bench.csv"
        if csv.exists():
            lines = csv.read_text().strip().splitlines()
            head = lines[0].split(",")
            for line in lines[1:]:
                d = dict(zip(head, line.split(",")))
                rows.append([f"`{d.get('example')}`", d.get("planner"), d.get("feasible"), sig(float(d["plan s"])) if d.get("plan s") not in (None, "", "-") else "-",
                             d.get("iterations"), d.get("horizon"), d.get("min robust margin")])
        else:
            rows.append(["-", "FAILED", one_line(error_reason(r), 12), "-", "-", "-", "-"])
        L = ["## Planner comparison", "",
             "Each installed planner on the same problems: the eps-robust plan only (no tracking), with the "
             "horizon search, so a planner that fails is tried at up to four horizons; \"feasible\" means the exact "
             "eps-robust check passed (at and between the samples). Costs are each planner's own objective and are "
             "not comparable across planners; iterations and reasons: docs/benchmarks-planners.md.", ""]
        L += code([f"{self.mshow} bench --stage plan --no-track --examples {','.join(examples)} --out {out}   # bench.md, bench.csv"])
        L.append("")
        L += table(["example", "planner", "feasible", "plan s", "iterations", "horizon", "smallest robust margin"], rows)
        return L

    # d. Large teams
    def field(self, sizes):
        rows, preds = [], []
        fdir = self.work / "field"
        fdir.mkdir(parents=True, exist_ok=True)
        for n in sizes:
            problem = fdir / f"field{n}.yaml"
            subprocess.run([sys.executable, ROOT / "scripts" / "unicycle_field.py", str(n), "--out", problem], check=True,
                           capture_output=True)
            c = run([self.m, "check", problem], timeout=600)
            m = re.search(r"^memory\s+planning about ([0-9.e+]+) (bytes|KiB|MiB|GiB|TiB)", c["stdout"], re.M)
            predicted = size_text(float(m.group(1)) * UNITS[m.group(2)]) if m else \
                ("refused: " + one_line(error_reason(c), 8) if c["rc"] else "-")
            preds.append(predicted)
            log(f"check field{n}: {c['wall']:.1f} s, {c['peak_kb'] / 1024:.0f} MB")
            r = solve(self.m, problem, fdir / f"field{n}", self.a, extra=["--time-limit", f"{self.a.time_limit:g}"])
            plan, track, certify, verify, total = stage_times(r["result"])
            agents = (r["result"] or {}).get("agents", [])
            have = sum(1 for x in agents if x.get("tracker", {}).get("status") == "controller")
            rows.append([n, predicted, mb(c["peak_kb"]), r["status"], f"{have} of {len(agents)}" if agents else "-",
                         sig(plan), sig(track), sig(certify), sig(verify), sig(r["wall"]), mb(r["peak_kb"])])
            self.now[f"field:{n}:total"] = r["wall"]
            self.now[f"field:{n}:status"] = f"{r['status']}, {sig(r['wall'])} s"
        self.now["field:pred"] = " / ".join(preds) + f" ({' / '.join(map(str, sizes))} robots)"
        L = ["## Large teams: the unicycle field", "",
             "N unicycles 2 m apart, shuffled within blocks of 5 x 5 among pillars (`scripts/unicycle_field.py`: the "
             "ten drones' parameters, T = 123), `tracker: auto`. `check` gives the plan's memory as predicted by the "
             "planner (`Planner::memory`) and its own peak (the problem loaded, the plugins open); `solve` runs the "
             f"whole method under a search budget of {self.a.time_limit:g} s. Stage times from result.json; peak is the "
             "whole command's resident set.", ""]
        L += code([f"python3 scripts/unicycle_field.py N --out {fdir}/fieldN.yaml   # N = {', '.join(map(str, sizes))}",
                   f"/usr/bin/time -f \"%e s %M KB\" {self.mshow} check {fdir}/fieldN.yaml",
                   f"/usr/bin/time -f \"%e s %M KB\" {self.mshow} solve {fdir}/fieldN.yaml --time-limit {self.a.time_limit:g} "
                   f"--out {fdir}/fieldN"])
        L.append("")
        L += table(["robots", "plan memory predicted", "check peak MB", "solve status", "controllers", "plan s",
                    "track s", "certify s", "verify s", "total s", "solve peak MB"], rows)
        if 1000 not in sizes:
            L += ["", "1000 robots: `python3 scripts/benchmarks.py --large` (not run by default: a plan of several minutes "
                  "and about 2.5 GB)."]
        L += ["", "25 to 1000 robots in one process and over two MPI ranks, each stage's memory beside `check`'s "
              "prediction, with plots: [benchmarks-field.md](benchmarks-field.md) (`python3 scripts/field_scale.py`)."]
        return L

    # e. Exported controllers
    def export(self):
        cc = shutil.which("cc") or shutil.which("gcc")
        size = shutil.which("size")
        edir = self.work / "export"
        shutil.rmtree(edir, ignore_errors=True)
        rows = []
        for ex, agent, which in EXPORT_ROWS:
            r = self.solves.get(ex) if which == "solve" else self.forced.get((ex, "abcd"))
            if not r or not r["result"]:
                continue
            folder = self.work / "solve" / ex if which == "solve" else self.work / "trackers" / f"{ex}-abcd"
            ctrl = folder / f"{agent}.ctrl"
            if not ctrl.exists():
                continue
            a = next((x for x in r["result"].get("agents", []) if x.get("name") == agent), {})
            tracker = a.get("tracker", {}).get("name", "?")
            n = len(a.get("eps", [])) or "-"
            T = r["result"].get("plan", {}).get("horizon", "-")
            dst = edir / f"{ex}-{which}"
            e = run([self.m, "export", ctrl, "--format", "c", "--out", dst], timeout=600)
            m = re.search(r"const data (\d+) bytes", e["stdout"])
            enc = re.search(r"(dense|rle) tables", e["stdout"])
            data = int(m.group(1)) if m else None
            text = "-"
            if cc and size and e["rc"] == 0:
                src = dst / f"{agent}.c"
                obj = dst / f"{agent}.o"
                c = run([cc, "-std=c99", "-Os", "-c", src, "-o", obj], timeout=1800)
                if c["rc"] == 0:
                    s = subprocess.run([size, obj], capture_output=True, text=True).stdout.splitlines()
                    text = size_text(int(s[-1].split()[0])) if len(s) > 1 else "-"
                else:
                    text = "cc failed"
                log(f"export {agent} ({ex}, {tracker}): cc -Os {c['wall']:.1f} s")
            label = f"{agent} (`{ex}`{', all abcd' if which == 'abcd' else ''})"
            rows.append([label, tracker, n, T, size_text(ctrl.stat().st_size),
                         (enc.group(1) if enc else ("one layout" if tracker == "funnel" else "-")),
                         size_text(data) if data is not None else "FAILED: " + one_line(error_reason(e), 8), text])
            if agent == "crane" and which == "abcd":
                self.now["export:crane-abcd"] = size_text(data) + f" ({enc.group(1) if enc else '-'})"
        L = ["## Exported controllers", "",
             "`marsyn export --format c` (docs/deploy.md) on controllers of the runs above: the `.ctrl` file, the "
             "encoding `auto` chose for abcd's tables (funnel controllers have one layout), the const data the command "
             "reports (what goes to flash besides about 0.5 KB of lookup code) and the object's `text` under "
             f"`{pathlib.Path(cc).name if cc else 'cc'} -std=c99 -Os`. Lookup time per call: "
             "`examples/deploy_c/measure.sh` (docs/deploy.md).", ""]
        L += code([f"{self.mshow} export {self.work}/solve/multi_drone/drone1.ctrl --format c --out {edir}/multi_drone-solve",
                   f"cc -std=c99 -Os -c {edir}/multi_drone-solve/drone1.c -o drone1.o && size drone1.o"])
        L.append("")
        L += table(["controller (example)", "tracker", "n", "T", "`.ctrl`", "encoding", "const data", "object text (-Os)"], rows)
        return L

    # g. History
    def history(self):
        rows = []
        for what, then, where, key in HISTORY:
            now = "-"
            if key and key.startswith("solve:") and key.count(",") and key.endswith(":total"):
                names = key.split(":")[1].split(",")
                vals = [self.now.get(f"solve:{x}:total") for x in names]
                now = (" / ".join(sig(v) for v in vals) + " s") if all(v is not None for v in vals) \
                    else "not measured in this run"
            elif key in self.now and self.now[key] is not None:
                v = self.now[key]
                now = v if isinstance(v, str) else f"{sig(v)} s"
            else:
                now = "not measured in this run" + {"global:time": " (`--global`)",
                                                    "field:1000:status": " (`--large`)"}.get(key, "")
            rows.append([what, then, where, now])
        L = ["## How the figures moved", "",
             "A few figures as the earlier diary of this file gave them (its sections by date and name: "
             "`git show f9b6c78:docs/benchmarks.md`; the whole history: `git log -p docs/benchmarks.md`), beside this "
             "run's. Early figures were taken under the sampled guarantee, several under load on a shared machine; "
             "they are what was measured then, not a like-for-like series.", ""]
        L += table(["figure", "then", "when (diary section)", "now (this run)"], rows)
        return L


def stale_binary_note(marsyn, commit):
    """The figures are the binary's: say so when it was built before the commit the header names."""
    try:
        committed = int(git("log", "-1", "--format=%ct", commit) or 0)
        built = pathlib.Path(marsyn).stat().st_mtime
    except (OSError, ValueError):
        return ""
    if committed and built < committed:
        return (", with a binary built before that commit (its figures are of an earlier build: rebuild and "
                "run it again)")
    return ""


def header(args, seconds, marsyn):
    commit, dirty = args.commit, args.dirty
    moved = git("rev-parse", "--short", "HEAD")
    cpu, cores, mem, osname, flags = machine()
    btype, bflags, cxx, version, built = build_info(marsyn)
    L = ["# Benchmarks", "",
         f"Generated by scripts/benchmarks.py at commit {commit}"
         + (" with uncommitted changes" if dirty else "") + f", {args.started} (UTC), in {seconds / 60:.0f} min"
         + (f" (HEAD was {moved} when it ended)" if moved and moved != commit else "")
         + stale_binary_note(marsyn, commit)
         + (" (`--quick`: a few examples, a small field)" if args.quick else "") + ". Do not edit by hand: run it again.", "",
         f"- machine: {cpu}, {cores} cores ({flags or 'no AVX2'}), {mem / 2 ** 30:.1f} GiB memory, {osname}; "
         f"1-minute load average {args.load_start} before the runs, {loadavg()} after, "
         f"{max((x for x in LOADS if x != '?'), key=float, default='?')} at most as a run started",
         f"- build: {btype} (`{bflags}`), {cxx}; {version}; binary `{rel(marsyn)}` built {built}",
         "- marsyn's defaults: two threads, 1000 closed-loop verification runs, continuous-time guarantee "
         "(where a file does not say `guarantee: sampled`); sizes in decimal units (1 MB = 10^6 bytes), peak memory "
         "is the command's largest resident set", "",
         "```sh",
         "python3 scripts/benchmarks.py            # regenerate this file (--quick to try, --large: 1000 robots too)",
         "```", "",
         "What the figures are worth: one run each, on one machine. Absolute times vary up to 2x between machines "
         "of this kind, and on a 2-core machine a second job (a build, another solve) doubles them; compare "
         "figures within a table. Instruction counts, per-stage profiles and the measurements behind each change "
         "are in the commit messages and in the earlier diary of this file (`git log -p docs/benchmarks.md`). "
         "Per stage in more depth: [benchmarks-altro.md](benchmarks-altro.md) (the default planner), "
         "[benchmarks-tracker.md](benchmarks-tracker.md) (abcd), [benchmarks-planners.md](benchmarks-planners.md) "
         "(the planners compared); the funnel's own costs: [funnel.md](funnel.md).", ""]
    return L


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--marsyn", default=str(ROOT / "build" / "bin" / "marsyn"))
    p.add_argument("--quick", action="store_true", help="a few examples and only the field of 25: to try the script")
    p.add_argument("--large", action="store_true", help="also the field of 1000 robots")
    p.add_argument("--time-limit", type=float, default=600,
                   help="the search's budget per solve in seconds (default 600); a run is stopped at 1.2 x it + 60 s")
    p.add_argument("--compare-limit", type=float,
                   help="the budget of each forced-tracker solve (table b; default 300 s, 60 s with --quick)")
    p.add_argument("--global", dest="global_baseline", action="store_true",
                   help="also global_baseline.yaml's global ABCD (the product abstraction): about 25 minutes")
    p.add_argument("--global-budget", type=float, default=6e9,
                   help="with --global: the solve's --global-budget (default 6e9 bytes, above its estimate)")
    p.add_argument("--examples", help="comma-separated example names (default: every examples/*.yaml)")
    p.add_argument("--work", default="/tmp/marsyn-bench", help="folder for the runs' outputs (default /tmp/marsyn-bench)")
    p.add_argument("--out", default=str(ROOT / "docs" / "benchmarks.md"))
    p.add_argument("--force-tracker", nargs=2, metavar=("TRACKER", "FILE"),
                   help="print FILE with every agent's tracker set to TRACKER (the copies table b solves) and exit")
    a = p.parse_args()

    if a.force_tracker:
        sys.stdout.write(force_tracker(pathlib.Path(a.force_tracker[1]).read_text(), a.force_tracker[0]))
        return

    if a.compare_limit is None:
        a.compare_limit = 60 if a.quick else 300
    a.marsyn = str(pathlib.Path(a.marsyn).resolve()) if os.sep in a.marsyn else a.marsyn
    if not shutil.which(a.marsyn):
        sys.exit(f"no marsyn at {a.marsyn} (build it, or give --marsyn)")
    a.started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M")
    a.commit = git("rev-parse", "--short", "HEAD") or "unknown"
    a.dirty = bool(git("status", "--porcelain", "--untracked-files=no"))
    a.load_start = loadavg()
    start = time.monotonic()
    pathlib.Path(a.work).mkdir(parents=True, exist_ok=True)

    files = sorted((ROOT / "examples").glob("*.yaml"))
    if a.examples:
        wanted = a.examples.split(",")
        files = [f for f in files if f.stem in wanted]
    elif a.quick:
        files = [f for f in files if f.stem in DEFAULT_QUICK_EXAMPLES]
    examples = [f for f in files if is_problem(f)]
    skipped = [f for f in files if not is_problem(f)]
    sizes = [25] if a.quick else [25, 100, 400] + ([1000] if a.large else [])
    planner_examples = ["pendulum"] if a.quick else PLANNER_EXAMPLES

    b = Bench(a)
    body = []
    body += b.end_to_end(examples, skipped) + [""]
    if a.global_baseline and any(f.stem == "global_baseline" for f in examples):
        body += b.global_baseline() + [""]
    body += b.trackers(examples) + [""]
    body += b.paper() + [""]
    body += b.planners(planner_examples) + [""]
    body += b.field(sizes) + [""]
    body += b.export() + [""]
    body += b.history()
    seconds = time.monotonic() - start
    text = "\n".join(wrap(header(a, seconds, a.marsyn) + body)) + "\n"
    pathlib.Path(a.out).write_text(text)
    n = text.count("\n")
    log(f"wrote {a.out}: {n} lines in {seconds / 60:.1f} min" + (f" (more than {LIMIT_LINES})" if n > LIMIT_LINES else ""))


if __name__ == "__main__":
    main()
