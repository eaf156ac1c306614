"""Checks an SRDF's disabled link pairs against the real Pinocchio + Coal on the URDF's collision geometry.

usage: srdf_pinocchio.py ROBOT.urdf PACKAGE_DIR ROBOT.srdf CONFIGS SEED
Loads the model and its COLLISION geometry as geometry_pinocchio.py does, reads the SRDF's
<disable_collisions link1 link2 reason> (xml.etree: the reasons matter) and, for every pair whose reason
is Default, Always or Never (Adjacent and User are not claims about geometry), decides with coal.collide
whether any collision geometry of link1 touches any of link2 at:
  "home": each joint at 0, or the middle of its limits where 0 is outside them (continuous joints 0);
  0..CONFIGS-1: uniform within each joint's limits (continuous joints in [-pi, pi]), drawn with
                numpy.random.default_rng(SEED), one value per actuated non-mimic joint in URDF order.
Mimic joints follow their leader (value = multiplier * leader + offset, from the URDF's <mimic>).
Prints one JSON object:
  configs:    CONFIGS;
  pairs:      {"Default": n, "Always": n, "Never": n}, the distinct pairs checked per reason;
  violations: [{link1, link2, reason, kind, config, q}], kind one of
              "default-apart-at-home" (a Default pair apart at home),
              "always-apart"          (an Always pair apart in some configuration; the first one),
              "never-collides"        (a Never pair colliding in some configuration; the first one);
              config is "home" or the random configuration's index, q every movable joint's value.
Timing goes to stderr.
"""
import json
import math
import sys
import time
import xml.etree.ElementTree as ET

import coal
import numpy as np
import pinocchio as pin

CHECKED = ("Default", "Always", "Never")
# Slack on the bounding-sphere rejection (m): spheres farther apart than this certainly do not touch.
SPHERE_SLACK = 1e-6

t_start = time.perf_counter()
urdf, package_dir, srdf = sys.argv[1], sys.argv[2], sys.argv[3]
n_configs, seed = int(sys.argv[4]), int(sys.argv[5])
model = pin.buildModelFromUrdf(urdf)
geom = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.COLLISION, package_dirs=[package_dir])
data = model.createData()
gdata = pin.GeometryData(geom)


def fail(message):
    print(f"srdf_pinocchio.py: {message}", file=sys.stderr)
    sys.exit(2)


# --- The URDF's joints (limits, mimic) and links, as scm reads them. ---
robot = ET.parse(urdf).getroot()
link_names = {l.get("name") for l in robot.findall("link")}
joints = {}  # name -> {"type", "lower", "upper", "mimic": (leader, multiplier, offset) | None}
order = []  # movable joints in URDF order
for j in robot.findall("joint"):
    kind = j.get("type")
    if kind not in ("revolute", "continuous", "prismatic"):
        continue
    limit = j.find("limit")
    lower = float(limit.get("lower", 0)) if limit is not None else 0.0
    upper = float(limit.get("upper", 0)) if limit is not None else 0.0
    if kind == "continuous":
        lower, upper = -math.pi, math.pi
    m = j.find("mimic")
    mimic = None
    if m is not None:
        mimic = (m.get("joint"), float(m.get("multiplier", 1)), float(m.get("offset", 0)))
    joints[j.get("name")] = {"type": kind, "lower": lower, "upper": upper, "mimic": mimic}
    order.append(j.get("name"))
dofs = [n for n in order if joints[n]["mimic"] is None]
lower = np.array([joints[n]["lower"] for n in dofs])
upper = np.array([joints[n]["upper"] for n in dofs])

model_joints = {model.names[jid]: model.joints[jid] for jid in range(1, model.njoints)}
for name, joint in model_joints.items():
    if name not in joints:
        fail(f"Pinocchio's joint \"{name}\" is not a movable URDF joint")
    if joint.nq not in (1, 2):
        fail(f"joint \"{name}\" has {joint.nq} configuration values")
if len(getattr(model, "mimicking_joints", [])) > 0:
    fail("Pinocchio built mimic joints; this checker sets them from the URDF itself")


def values_of(dof_values):
    """Every movable joint's value: the DOFs', then each mimic from its leader (value = m * leader + o)."""
    values = dict(zip(dofs, (float(v) for v in dof_values)))

    def value(name, depth=0):
        if name not in values:
            if depth > len(order):
                fail(f"mimic joints loop through \"{name}\"")
            leader, multiplier, offset = joints[name]["mimic"]
            if leader not in joints:
                fail(f"joint \"{name}\" mimics \"{leader}\", not a movable joint")
            values[name] = multiplier * value(leader, depth + 1) + offset
        return values[name]

    for name in order:
        value(name)
    return {name: values[name] for name in order}


def q_of(values):
    """Pinocchio's configuration vector for the joint values (cos/sin for unbounded joints)."""
    q = pin.neutral(model)
    for name, joint in model_joints.items():
        v = values[name]
        if joint.nq == 1:
            q[joint.idx_q] = v
        else:
            q[joint.idx_q], q[joint.idx_q + 1] = math.cos(v), math.sin(v)
    return q


home = values_of([0.0 if lo <= 0.0 <= hi else 0.5 * (lo + hi) for lo, hi in zip(lower, upper)])
rng = np.random.default_rng(seed)
draws = rng.uniform(lower, upper, size=(n_configs, len(dofs))) if n_configs > 0 else np.zeros((0, len(dofs)))
configurations = [("home", home)] + [(k, values_of(draws[k])) for k in range(n_configs)]

# --- Collision geometry per link, with a bounding sphere in the geometry's own frame. ---
geoms_of = {}  # link -> [geometry index]
centers, radii = [], []
for i, go in enumerate(geom.geometryObjects):
    frame = model.frames[go.parentFrame]
    if frame.type != pin.FrameType.BODY or frame.name not in link_names:
        fail(f"geometry \"{go.name}\" hangs from frame \"{frame.name}\" ({frame.type}), not a URDF link")
    geoms_of.setdefault(frame.name, []).append(i)
    g = go.geometry
    g.computeLocalAABB()
    centers.append(np.asarray(g.aabb_center, dtype=float).copy())
    radii.append(float(g.aabb_radius))
centers, radii = np.array(centers), np.array(radii)

# --- The SRDF's disabled pairs. ---
pairs = []  # (link1, link2, reason), each unordered pair once
seen = {}
for d in ET.parse(srdf).getroot().iter("disable_collisions"):
    a, b, reason = d.get("link1"), d.get("link2"), d.get("reason", "")
    for link in (a, b):
        if link not in link_names:
            fail(f"the SRDF disables a pair with \"{link}\", not a link of the URDF")
    key = frozenset((a, b))
    if key in seen:
        if seen[key] != reason:
            print(f"note: {a} / {b} is listed as {seen[key]} and as {reason}; the first counts",
                  file=sys.stderr)
        continue
    seen[key] = reason
    if reason in CHECKED:
        pairs.append((a, b, reason))
counts = {r: sum(1 for p in pairs if p[2] == r) for r in CHECKED}

# Per checked pair, its geometry pairs (indices into the flat arrays gi, gj).
gi, gj, owner = [], [], []
for p, (a, b, _) in enumerate(pairs):
    for i in geoms_of.get(a, []):
        for j in geoms_of.get(b, []):
            gi.append(i)
            gj.append(j)
            owner.append(p)
gi, gj, owner = np.array(gi, dtype=int), np.array(gj, dtype=int), np.array(owner, dtype=int)
reach = radii[gi] + radii[gj] + SPHERE_SLACK if len(gi) else np.zeros(0)

t_loaded = time.perf_counter()
n_collide = 0
violations = []
open_pairs = {p for p, (_, _, r) in enumerate(pairs) if r in ("Always", "Never")}
kinds = {"Default": "default-apart-at-home", "Always": "always-apart", "Never": "never-collides"}
request = coal.CollisionRequest()

for config, values in configurations:
    pin.forwardKinematics(model, data, q_of(values))
    pin.updateFramePlacements(model, data)
    pin.updateGeometryPlacements(model, data, geom, gdata)
    placements = [gdata.oMg[i] for i in range(len(geom.geometryObjects))]
    world = np.array([m.rotation @ c + m.translation for m, c in zip(placements, centers)])
    near = np.linalg.norm(world[gi] - world[gj], axis=1) <= reach if len(gi) else np.zeros(0, dtype=bool)
    transforms = {}

    def collide(i, j):
        global n_collide
        for k in (i, j):
            if k not in transforms:
                transforms[k] = coal.Transform3s(placements[k].rotation, placements[k].translation)
        n_collide += 1
        result = coal.CollisionResult()
        coal.collide(geom.geometryObjects[i].geometry, transforms[i],
                     geom.geometryObjects[j].geometry, transforms[j], request, result)
        return result.isCollision()

    # Whether each pair to decide collides here: any of its geometry pairs whose spheres meet, collides.
    decide = open_pairs | ({p for p, pr in enumerate(pairs) if pr[2] == "Default"} if config == "home" else set())
    touching = set()
    for k in np.nonzero(near)[0]:
        p = int(owner[k])
        if p in decide and p not in touching and collide(int(gi[k]), int(gj[k])):
            touching.add(p)
    for p in sorted(decide):
        a, b, reason = pairs[p]
        if (reason == "Never") == (p in touching):
            violations.append({"link1": a, "link2": b, "reason": reason, "kind": kinds[reason],
                               "config": config, "q": values})
            open_pairs.discard(p)
    if not open_pairs:
        break

t_end = time.perf_counter()
print(f"srdf_pinocchio.py: {len(pairs)} pairs ({counts}), {len(configurations)} configurations, "
      f"{n_collide} coal.collide calls; load {t_loaded - t_start:.2f} s, check {t_end - t_loaded:.2f} s",
      file=sys.stderr)
print(json.dumps({"configs": n_configs, "pairs": counts, "violations": violations}))
