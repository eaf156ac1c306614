#!/usr/bin/env python3
"""Summarises the `never` certificates of sampled URDDs, as docs/benchmarks.md reports them.

usage: scripts/certify-report.py DIR [DIR ...]
For each URDD (after `scm sample`): one markdown table row (never pairs, certified, sampled by cause,
overturned, boxes in all and for the largest certified pair), then the pairs that resisted: their
certificate's status, boxes, cleared share of the joint box, proved lower bound and closest approach.
"""
import json
import pathlib
import sys

rows, resisted = [], []
for d in sys.argv[1:]:
    path = pathlib.Path(d) / "sample" / "mesh.json"
    mesh = json.loads(path.read_text())
    s = mesh["summary"]
    never = s["reasons"].get("never", 0)
    certs = [p["certificate"] for p in mesh["pairs"] if p.get("certificate")]
    certified = [c["boxes"] for c in certs if c["status"] == "certified"]
    by_status = {}
    for c in certs:
        by_status[c["status"]] = by_status.get(c["status"], 0) + 1
    name = pathlib.Path(d).name
    share = 100.0 * s["certified"] / never if never else 100.0
    rows.append(
        f"| {name} | {never} | {s['certified']} ({share:.1f}%) | {by_status.get('budget', 0)} | "
        f"{by_status.get('hulls-touch', 0)} | {s['overturned']} | {s['boxes']:,} | "
        f"{max(certified, default=0):,} |"
    )
    for p in mesh["pairs"]:
        c = p.get("certificate")
        if c and c["status"] != "certified":
            resisted.append(
                f"| {name} | {p['link1']} - {p['link2']} | {c['status']} | {c['boxes']:,} | "
                f"{100.0 * c['cleared']:.1f}% | {1000.0 * c['lower_bound']:.2f} mm | "
                f"{1000.0 * c['closest']:.2f} mm |"
            )

print("| robot | never | certified | budget spent | hulls touch | overturned | boxes | largest certified |")
print("|---|---|---|---|---|---|---|---|")
print("\n".join(rows))
if resisted:
    print()
    print("| robot | pair | status | boxes | cleared | proved lower bound | closest found |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(resisted))
