#!/usr/bin/env python3
"""Check that a change leaves marsyn's products unchanged: solve every example with two builds
and compare what they wrote.

    scripts/compare_outputs.py --ref /tmp/main-tree/bin/marsyn --new build/bin/marsyn --out /tmp/cmp
    scripts/compare_outputs.py --compare /tmp/cmp/ref /tmp/cmp/new     # compare folders only

Each build solves examples/*.yaml and examples/auto/*.yaml (20 verification runs, 2 threads) into
OUT/ref/<example> and OUT/new/<example>. Then, per example: every controller file (*.ctrl) must be
byte-identical, and plan.json and result.json identical as JSON once the measured fields are left
out (keys ending in _s or containing "time": wall-clock times; peak_memory_bytes: measured RSS;
in text, a number followed by " s", e.g. "certified after 2 rounds and 2.25 s").
A binary finds its plugins next to itself (../lib/marsyn/plugins), so copy a reference build's
bin/ and lib/ together. Exit status 1 on any difference.
"""
import argparse
import difflib
import filecmp
import json
import pathlib
import re
import subprocess
import sys


def measured(key):
    return key.endswith("_s") or "time" in key or key == "peak_memory_bytes"


SECONDS = re.compile(r"\b\d+(?:\.\d+)?(?:e[-+]?\d+)? s\b")


def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not measured(k)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    if isinstance(x, str):
        return SECONDS.sub("<seconds> s", x)
    return x


def solve_all(binary, examples, out):
    out.mkdir(parents=True, exist_ok=True)
    for f in examples:
        name = f.stem if f.parent.name == "examples" else f"{f.parent.name}_{f.stem}"
        with open(out / f"{name}.log", "w") as log:
            rc = subprocess.call([binary, "solve", str(f), "--out", str(out / name), "--runs", "20", "--threads", "2"],
                                 stdout=log, stderr=subprocess.STDOUT)
        print(f"{binary}: {name} exit {rc}", flush=True)


def json_differs(a, b):
    x, y = strip(json.load(open(a))), strip(json.load(open(b)))
    if x == y:
        return []
    lx = json.dumps(x, indent=1, sort_keys=True).splitlines()
    ly = json.dumps(y, indent=1, sort_keys=True).splitlines()
    return list(difflib.unified_diff(lx, ly, lineterm="", n=1))[2:22]


def compare(ref, new):
    differences = 0
    for r in sorted(p for p in ref.iterdir() if p.is_dir()):
        n = new / r.name
        pick = lambda d: sorted(f.name for f in d.iterdir() if f.suffix == ".ctrl" or f.name in ("plan.json", "result.json"))
        if not n.is_dir():
            print(f"{r.name}: missing in {new}")
            differences += 1
            continue
        rf, nf = pick(r), pick(n)
        here = 0
        if rf != nf:
            print(f"  files differ: {rf} vs {nf}")
            here += 1
        for f in (f for f in rf if f in nf):
            if f.endswith(".json"):
                if diff := json_differs(r / f, n / f):
                    print(f"  {r.name}/{f} differs:\n      " + "\n      ".join(diff))
                    here += 1
            elif not filecmp.cmp(r / f, n / f, shallow=False):
                print(f"  {r.name}/{f} differs (bytes)")
                here += 1
        print(f"{r.name}: {'same' if not here else 'DIFFERENT'} ({len(rf)} files)")
        differences += here
    print(f"differences: {differences}")
    return differences


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ref", help="the reference marsyn binary")
    ap.add_argument("--new", help="the changed marsyn binary")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("/tmp/marsyn-compare"))
    ap.add_argument("--compare", nargs=2, type=pathlib.Path, metavar=("REF_DIR", "NEW_DIR"))
    a = ap.parse_args()
    if a.compare:
        sys.exit(1 if compare(*a.compare) else 0)
    if not a.ref or not a.new:
        ap.error("give --ref and --new, or --compare")
    root = pathlib.Path(__file__).resolve().parent.parent / "examples"
    examples = sorted(root.glob("*.yaml")) + sorted((root / "auto").glob("*.yaml"))
    solve_all(a.ref, examples, a.out / "ref")
    solve_all(a.new, examples, a.out / "new")
    sys.exit(1 if compare(a.out / "ref", a.out / "new") else 0)


if __name__ == "__main__":
    main()
