"""Loads a URDF's collision geometry with the real Pinocchio + Coal and reports it per link.

usage: geometry_pinocchio.py ROBOT.urdf PACKAGE_DIR CONFIGS.json
CONFIGS.json is a list of {joint name: value} (every movable joint, mimic joints included, as
`scm inspect --json` lists them). Prints one JSON object:
  configurations: per configuration, {link: {"count": geometries, "min": [x,y,z], "max": [x,y,z]}}
                  (exact world boxes: a mesh's placed vertices, a primitive's true shape);
  points:         {link: [[x,y,z], ...]}: every vertex of each mesh and points on each primitive's
                  surface, in the link frame, for checking that scm's link hull contains them.
"""
import json
import math
import sys

import coal
import numpy as np
import pinocchio as pin

urdf, package_dir, configs_path = sys.argv[1], sys.argv[2], sys.argv[3]
model = pin.buildModelFromUrdf(urdf)
geom = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.COLLISION, package_dirs=[package_dir])
data = model.createData()
gdata = pin.GeometryData(geom)


def link_of(go):
    return model.frames[go.parentFrame].name


def q_of(values):
    """Pinocchio's configuration vector for scm's joint values (cos/sin for unbounded joints)."""
    q = pin.neutral(model)
    for jid in range(1, model.njoints):
        name, joint = model.names[jid], model.joints[jid]
        if name not in values:
            continue
        v = values[name]
        if joint.nq == 1:
            q[joint.idx_q] = v
        elif joint.nq == 2:
            q[joint.idx_q], q[joint.idx_q + 1] = math.cos(v), math.sin(v)
    return q


def world_box(shape, placement):
    r, p = placement.rotation, placement.translation
    if isinstance(shape, coal.Box):
        e = np.abs(r) @ np.asarray(shape.halfSide)
    elif isinstance(shape, coal.Sphere):
        e = np.full(3, shape.radius)
    elif isinstance(shape, coal.Cylinder):
        a = r[:, 2]
        e = shape.halfLength * np.abs(a) + shape.radius * np.sqrt(np.clip(1 - a * a, 0, None))
    elif isinstance(shape, coal.Capsule):
        e = shape.halfLength * np.abs(r[:, 2]) + shape.radius
    else:
        v = np.asarray(shape.vertices()) @ r.T + p
        return v.min(axis=0), v.max(axis=0)
    return p - e, p + e


def surface_points(shape):
    """Vertices of a mesh; corners or points on the surface of a primitive, in the shape's frame."""
    if isinstance(shape, coal.Box):
        h = np.asarray(shape.halfSide)
        return np.array([[sx * h[0], sy * h[1], sz * h[2]]
                         for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    ring = np.linspace(0, 2 * math.pi, 97)[:-1]
    if isinstance(shape, coal.Cylinder):
        r, h = shape.radius, shape.halfLength
        return np.array([[r * math.cos(t), r * math.sin(t), z] for t in ring for z in (-h, h)])
    if isinstance(shape, (coal.Sphere, coal.Capsule)):
        r = shape.radius
        h = shape.halfLength if isinstance(shape, coal.Capsule) else 0.0
        pts = []
        for lat in np.linspace(-math.pi / 2, math.pi / 2, 25):
            for t in ring:
                z = r * math.sin(lat)
                z += h if z >= 0 else -h
                pts.append([r * math.cos(lat) * math.cos(t), r * math.cos(lat) * math.sin(t), z])
        return np.array(pts)
    return np.asarray(shape.vertices())


configs = json.load(open(configs_path))
out = {"configurations": [], "points": {}}
for values in configs:
    q = q_of(values)
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    pin.updateGeometryPlacements(model, data, geom, gdata)
    links = {}
    for i, go in enumerate(geom.geometryObjects):
        lo, hi = world_box(go.geometry, gdata.oMg[i])
        entry = links.setdefault(link_of(go), {"count": 0, "min": lo, "max": hi})
        entry["count"] += 1
        entry["min"], entry["max"] = np.minimum(entry["min"], lo), np.maximum(entry["max"], hi)
        if len(out["configurations"]) == 0:
            # The shape's points in its link's frame: oMf^-1 * oMg * point.
            to_link = data.oMf[go.parentFrame].inverse() * gdata.oMg[i]
            pts = surface_points(go.geometry) @ to_link.rotation.T + to_link.translation
            out["points"].setdefault(link_of(go), []).extend(pts.tolist())
    out["configurations"].append(
        {k: {"count": v["count"], "min": list(v["min"]), "max": list(v["max"])} for k, v in links.items()})
print(json.dumps(out))
