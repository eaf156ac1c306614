"""Loads scm's SRDF into the real Pinocchio and reports which collision pairs it removed.

usage: check_pinocchio.py ROBOT.urdf MESH_DIR EXPORTED.srdf
Builds the collision geometry model from the URDF, adds all collision pairs, applies the SRDF with
removeCollisionPairs, and prints one JSON line: the link pairs before and after (as sorted name pairs).
"""
import json, sys
import pinocchio as pin

urdf, mesh_dir, srdf = sys.argv[1], sys.argv[2], sys.argv[3]
model = pin.buildModelFromUrdf(urdf)
geom = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.COLLISION, package_dirs=[mesh_dir])


def link_pairs(g):
    out = set()
    for cp in g.collisionPairs:
        a = model.frames[g.geometryObjects[cp.first].parentFrame].name
        b = model.frames[g.geometryObjects[cp.second].parentFrame].name
        if a != b:
            out.add(tuple(sorted((a, b))))
    return out


geom.addAllCollisionPairs()
before = link_pairs(geom)
pin.removeCollisionPairs(model, geom, srdf)
after = link_pairs(geom)
print(json.dumps({"before": sorted(before), "after": sorted(after)}))
