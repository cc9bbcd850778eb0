#!/usr/bin/env python3
"""Compares two result.json files except timings and memory (docs/mpi.md: a run over R ranks
gives the result of one process). Usage: compare_results.py A B; exit 1 with the first difference."""
import json
import sys

# What legitimately differs between runs: wall-clock and CPU times, the peak memory of the
# reporting process and what each stage added to it (`memory`), and the search's stop message (it names the seconds the search took).
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items()
                if not (k.endswith("time_s") or k in ("peak_memory_bytes", "memory", "stop_message"))}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v

def first_difference(a, b, path="$"):
    if type(a) != type(b):
        return f"{path}: {a!r} vs {b!r}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}: only in {'second' if k not in a else 'first'}"
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} vs {len(b)} entries"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path}: {a!r} vs {b!r}"

a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
d = first_difference(a, b)
if d:
    print(f"result.json differs: {d}")
    sys.exit(1)
