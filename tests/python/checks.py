"""What the Python tests share: a fresh scratch folder, and checks that report every failure
before the script ends (one run shows all that differs from the CLI, not just the first)."""
import os
import shutil
import sys

failures = []


def fresh(folder):
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    return folder


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what, flush=True)


def finish(summary):
    """Exit 1 when any check failed, else print the summary."""
    if failures:
        print("%d failure(s)" % len(failures))
        sys.exit(1)
    print(summary)
