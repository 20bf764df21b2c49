#!/usr/bin/env python3
"""Compares two snapshots written by snapshot-outputs.sh: byte for byte, and for JSON files that
differ, as JSON values (so a change of key order is told apart from a change of content).

    python3 scripts/compare-outputs.py /tmp/before /tmp/after
"""
import json
import os
import sys


def diff(a, b, path=""):
    """Paths where two JSON values differ (key order ignored)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if k not in a:
                out.append(f"{path}.{k}: added")
            elif k not in b:
                out.append(f"{path}.{k}: removed")
            else:
                out += diff(a[k], b[k], f"{path}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in diff(x, y, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: {json.dumps(a)[:80]} -> {json.dumps(b)[:80]}"]


def main(before, after):
    identical = same_json = 0
    changed = []
    for root, _, files in os.walk(before):
        for f in sorted(files):
            p = os.path.join(root, f)
            q = os.path.join(after, os.path.relpath(p, before))
            rel = os.path.relpath(p, before)
            if not os.path.exists(q):
                changed.append((rel, ["missing after"]))
                continue
            a, b = open(p, "rb").read(), open(q, "rb").read()
            if a == b:
                identical += 1
            elif f.endswith(".json"):
                d = diff(json.loads(a), json.loads(b))
                if d:
                    changed.append((rel, d))
                else:
                    same_json += 1
                    print(f"{rel}: same JSON value, other key order")
            else:
                changed.append((rel, ["bytes differ"]))
    for rel, d in changed:
        print(f"{rel}:")
        for line in d[:12]:
            print(f"    {line}")
        if len(d) > 12:
            print(f"    ... {len(d) - 12} more")
    print(f"{identical} byte-identical, {same_json} equal as JSON, {len(changed)} changed")


if __name__ == "__main__":
    main(*sys.argv[1:3])
