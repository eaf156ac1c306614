#!/usr/bin/env python3
"""Write a synthetic robot for scale measurements: N links, each made of M separate convex pieces.

The robot is a chain (or a tree with --branches B > 1) of N links joined by N - 1 revolute joints
with limits. Every link carries M boxes as separate <collision> elements, spaced along the link with
gaps. Sizes, offsets, joint axes and limits come from a seeded generator: the same arguments write the
same bytes. Primitive geometry only (no mesh files); standard library only.

    python3 scripts/make_synthetic_robot.py --links 60 --pieces 3 [--branches 1] [--seed 0] [-o OUT]
    scm preprocess OUT/synthetic_n60_m3.urdf -o DIR --max-pieces 3

writes OUT/synthetic_n60_m3.urdf (OUT defaults to the current folder) and prints its path. With
--max-pieces M the decomposition keeps exactly the M boxes of every link (M up to 6; with the
default of 8 it finds 3 to 8 pieces on a 3-box link: slivers of the boxes' faces). Generated robots
are measurements' inputs, not sources: write them to a temporary folder, do not commit them.
"""
import argparse
import random
from pathlib import Path

LENGTH = 0.12  # m, from a link's joint to its children's joints, along the link's z axis
MARGIN = 0.006  # m from a joint to the nearest piece, on either side
GAPS = 0.3  # the fraction of a link's length between its pieces: the decomposition splits only when
#             the pieces are at least 15% smaller than the link's hull
WIDTH = (0.024, 0.04)  # m, range of a piece's width
SPLAY = 0.5  # rad between sibling branches of a tree


def num(x):
    return f"{x:.6g}"


def vec(v):
    return " ".join(num(x) for x in v)


def pieces(rng, m):
    """M boxes (geometry xml, origin xyz) along z in [MARGIN, LENGTH - MARGIN], gaps between them
    making up GAPS of that length. Boxes, because a box is convex in the decomposition's voxels too:
    it may shave a sliver off a box's face (merged back for free with --max-pieces M), while it cuts a
    tessellated cylinder or sphere into several pieces."""
    length = LENGTH - 2 * MARGIN
    gap = GAPS * length / (m - 1) if m > 1 else 0.0
    span = (length - gap * (m - 1)) / m
    out = []
    for k in range(m):
        z = MARGIN + k * (span + gap) + span / 2
        w = rng.uniform(*WIDTH)
        dx, dy = rng.uniform(-0.004, 0.004), rng.uniform(-0.004, 0.004)
        geometry = f'<box size="{vec((w, rng.uniform(*WIDTH), span))}"/>'
        out.append((geometry, (dx, dy, z)))
    return out


def link_xml(name, elements):
    out = [f'  <link name="{name}">']
    for tag in ("visual", "collision"):
        for geometry, xyz in elements:
            out += [f"    <{tag}>", f'      <origin xyz="{vec(xyz)}" rpy="0 0 0"/>',
                    f"      <geometry>{geometry}</geometry>", f"    </{tag}>"]
    return out + ["  </link>"]


def joint_xml(i, parent, sibling, siblings, rng):
    """The revolute joint from `parent` to link i: at the parent's tip, splayed when it has siblings."""
    roll = (sibling - (siblings - 1) / 2) * SPLAY
    axis = rng.choice([(1, 0, 0), (0, 1, 0), (0, 1, 0), (0, 0, 1)])
    lower, upper = -rng.uniform(1.2, 2.4), rng.uniform(1.2, 2.4)
    return [f'  <joint name="joint_{i}" type="revolute">', f'    <parent link="link_{parent}"/>',
            f'    <child link="link_{i}"/>', f'    <origin xyz="0 0 {num(LENGTH)}" rpy="{vec((roll, 0, 0))}"/>',
            f'    <axis xyz="{vec(axis)}"/>',
            f'    <limit lower="{num(lower)}" upper="{num(upper)}" effort="10" velocity="1"/>', "  </joint>"]


def urdf_text(links, m, branches, seed):
    """The URDF: link i's parent is (i - 1) // branches (a chain when branches is 1)."""
    rng = random.Random(seed)
    name = f"synthetic_n{links}_m{m}" + (f"_b{branches}" if branches > 1 else "")
    out = ['<?xml version="1.0"?>',
           f"<!-- written by scripts/make_synthetic_robot.py: links {links}, pieces {m}, branches {branches},"
           f" seed {seed} -->", f'<robot name="{name}">']
    for i in range(links):
        out += link_xml(f"link_{i}", pieces(rng, m))
        if i > 0:
            parent = (i - 1) // branches
            first = parent * branches + 1  # the parent's first child
            siblings = min(branches, links - first)
            out += joint_xml(i, parent, i - first, siblings, rng)
    return name, "\n".join(out + ["</robot>", ""])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--links", type=int, default=10, help="N, links (every one with geometry)")
    p.add_argument("--pieces", type=int, default=3, help="M, convex pieces per link")
    p.add_argument("--branches", type=int, default=1, help="children per link: 1 a chain, more a tree")
    p.add_argument("--seed", type=int, default=0, help="seed of sizes, offsets, axes and limits")
    p.add_argument("-o", "--out", type=Path, default=Path("."), help="output folder")
    a = p.parse_args()
    if a.links < 1 or a.pieces < 1 or a.branches < 1:
        p.error("--links, --pieces and --branches must be at least 1")
    if a.pieces > 16:
        p.error("--pieces: at most 16 (the decomposition keeps at most 64 pieces a link, 8 by default)")
    name, text = urdf_text(a.links, a.pieces, a.branches, a.seed)
    a.out.mkdir(parents=True, exist_ok=True)
    path = a.out / f"{name}.urdf"
    path.write_text(text)
    print(path)


if __name__ == "__main__":
    main()
