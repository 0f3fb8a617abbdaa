#!/usr/bin/env python3
"""Fails on any expression that draws from a random engine twice without a sequence point between
the draws: `Eigen::Vector3d(g(rng), g(rng), g(rng))`, `f(u(rng), u(rng))`, `u(rng) * a + u(rng) * b`.
C++ leaves the order of a call's arguments and of most operands unspecified, so such a line makes
one seed give g++ one cloud and clang another (g++ draws the last argument first, clang the first).
Draw into a vector with slipfit::randomVector (slipfit/sampling/random_vector.h) or into named
variables instead. Sequenced, and allowed: separate declarators (`double a = u(rng), b = u(rng);`),
the items of a braced list, the operands of &&, ||, ?:, << and >>, and a loop's condition and body.

    unsequenced_draws.py DIR...      prints file:line: statement for each, exits 1 if any
"""
import os
import re
import sys

DRAW = re.compile(r"\b\w+\((?:rng|rng_|gen|engine|generator)\)")
CONTROL = re.compile(r"\b(?:while|if|for|switch)\s*\(")


def strip(src):
    """The source with comments and string literals blanked, lengths kept."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif src[i] == '"' or (src[i] == "'" and not src[i - 1].isalnum()):
            q, j = src[i], i + 1
            while j < n and src[j] != q:
                j += 2 if src[j] == "\\" else 1
            j += 1
        else:
            out.append(src[i])
            i += 1
            continue
        out.append("".join(c if c == "\n" else " " for c in src[i:j]))
        i = j
    return "".join(out)


def segments(stmt):
    """The statement cut at its sequence points; each piece's draws are unsequenced."""
    pieces, start, stack, i = [], 0, [], 0
    m = CONTROL.search(stmt)
    if m:  # the condition, then the body
        depth, j = 0, m.end() - 1
        while j < len(stmt):
            depth += {"(": 1, ")": -1}.get(stmt[j], 0)
            if depth == 0:
                break
            j += 1
        return segments(stmt[m.end():j]) + segments(stmt[j + 1:])
    while i < len(stmt):
        c = stmt[i]
        cut = False
        if c in "([{":
            stack.append(c)
        elif c in ")]}":
            if stack:
                stack.pop()
        elif c == "," and (not stack or stack[-1] == "{"):
            cut = True
        elif stmt.startswith(("&&", "||", "<<", ">>"), i):
            pieces.append(stmt[start:i])
            start = i = i + 2
            continue
        elif c in "?:" and not stmt.startswith("::", i) and not stmt.startswith("::", i - 1):
            cut = True
        if cut:
            pieces.append(stmt[start:i])
            start = i + 1
        i += 1
    pieces.append(stmt[start:])
    return pieces


def check(path):
    src = strip(open(path, encoding="utf-8").read())
    found, start = [], 0
    for m in re.finditer(r"[;{}]", src):
        stmt = src[start:m.start()]
        if any(len(DRAW.findall(p)) >= 2 for p in segments(stmt)):
            first = DRAW.search(stmt)
            line = src.count("\n", 0, start + first.start()) + 1
            found.append(f"{path}:{line}: {' '.join(stmt.split())}")
        start = m.end()
    return found


def main(dirs):
    found = []
    for d in dirs:
        for root, _, files in os.walk(d):
            for f in sorted(files):
                if f.endswith((".cpp", ".h", ".hpp")):
                    found += check(os.path.join(root, f))
    for f in found:
        print(f)
    if found:
        print(f"unsequenced_draws: {len(found)} expressions draw twice in an unspecified order; "
              "use slipfit::randomVector or named draws")
        return 1
    print("unsequenced_draws: none")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
