#!/usr/bin/env python3
"""List C++ functions longer than a limit (default 80 lines): a brace counter.

    python3 scripts/long_functions.py            # the tracked sources, tests, bench, fuzz and python/ left out
    python3 scripts/long_functions.py --limit 100 --all
    python3 scripts/long_functions.py core/src/solve.cpp

Run from the repository's top (it asks git for the files). A function is counted from the line of
its opening brace to the line of its closing one; lambdas count within their function.

Strips comments, strings and character literals, then takes each outermost `{` whose header
(the text since the previous `;`, `{` or `}`) holds a `(` and is not a control statement,
namespace, class, struct, enum or initialiser as the start of a function body.
"""
import argparse
import pathlib
import re
import subprocess
import sys

NOT_FUNCTION = re.compile(r'^\s*(namespace|class|struct|union|enum|extern\s+"C")\b')
CONTROL = re.compile(r'\b(if|for|while|switch|catch|do|else|try)\s*$')


def strip(text):
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            i = n if j < 0 else j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            k = text.find('(', i)
            delim = ')' + text[i + 2:k] + '"'
            j = text.find(delim, k)
            j = n if j < 0 else j + len(delim)
            out.append('""' + re.sub(r'[^\n]', '', text[i:j]))
            i = j
        elif c in '"\'':
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                out.append(c); i += 1; continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == '\\' else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def functions(path):
    text = strip(path.read_text(errors='replace'))
    text = re.sub(r'(?m)^[ \t]*#.*(\\\n.*)*$', lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    depth, fn_depth, start, header_from = 0, None, 0, 0
    for i, c in enumerate(text):
        if c == '{':
            if fn_depth is None:
                header = text[header_from:i]
                h = header.strip()
                if '(' in h and not NOT_FUNCTION.match(h) and not CONTROL.search(h.split(')')[0].split('(')[0]) \
                        and not h.endswith('=') and not re.search(r'=\s*\[', h) and not h.endswith(','):
                    fn_depth, start = depth, i
                    name = re.sub(r'\s+', ' ', h)
            depth += 1
            header_from = i + 1
        elif c == '}':
            depth -= 1
            header_from = i + 1
            if fn_depth is not None and depth == fn_depth:
                first = text.count('\n', 0, start) + 1
                last = text.count('\n', 0, i) + 1
                sig = name.split('(')[0].split()[-1] if name.split('(')[0].split() else name[:40]
                yield first, last, sig
                fn_depth = None
        elif c == ';':
            header_from = i + 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('--all', action='store_true', help='include tests and bindings')
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    files = a.paths or subprocess.run(['git', 'ls-files', '*.cpp', '*.hpp', '*.h', '*.cc'],
                                      capture_output=True, text=True).stdout.split()
    rows = []
    for f in files:
        if not a.all and (re.search(r'(^|/)(tests?|fuzz|bench)/', f) or f.startswith('python/')
                          or '_test' in f):
            continue
        p = pathlib.Path(f)
        for first, last, name in functions(p):
            if last - first + 1 > a.limit:
                rows.append((last - first + 1, f, first, name))
    for length, f, first, name in sorted(rows, reverse=True):
        print(f'{length:5d} {f}:{first} {name}')
    print(f'{len(rows)} functions over {a.limit} lines', file=sys.stderr)


if __name__ == '__main__':
    main()
