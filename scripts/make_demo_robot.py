#!/usr/bin/env python3
"""Generate robots/demo_arm/: the scm demo robot (a 7-DOF arm with a 2-finger gripper).

Everything is authored here: the URDF, the meshes (binary/ASCII STL, OBJ, COLLADA), package.xml
and README.md. Standard library only; the output is byte-for-byte deterministic (no timestamps).

    python3 scripts/make_demo_robot.py [OUT_DIR]     # default: robots/demo_arm next to scripts/

Frames and meshes are in metres. A mesh is (vertices, triangles): a closed surface whose
triangles are counter-clockwise seen from outside. Builders make meshes in the frame of the
<collision> element that uses them; writers convert to the file's own coordinates.
"""
import math
import struct
import sys
from pathlib import Path

PI = math.pi
HALF_PI = PI / 2
SEG = 48  # segments around a solid of revolution

# ---------------------------------------------------------------- 2D profile helpers


def arc(cx, cy, r, a0, a1, n):
    """n+1 points on the circle (cx, cy, r) from angle a0 to a1 (degrees), ends included."""
    return [(cx + r * math.cos(math.radians(a0 + (a1 - a0) * i / n)),
             cy + r * math.sin(math.radians(a0 + (a1 - a0) * i / n))) for i in range(n + 1)]


def rounded_profile(z0, z1, r0, r1, fillet, n=4):
    """(r, z) outline of a round bar from z0 (radius r0) to z1 (radius r1) with filleted edges."""
    return ([(0.0, z0)] + arc(r0 - fillet, z0 + fillet, fillet, -90, 0, n)
            + arc(r1 - fillet, z1 - fillet, fillet, 0, 90, n) + [(0.0, z1)])


def round_corners(poly, radius, n=4):
    """Replace the corners of a polygon by tangent arcs (convex or reflex corners alike).
    radius: one radius for all corners, or one per corner (0 keeps the corner)."""
    out = []
    for i, p in enumerate(poly):
        r = radius[i] if isinstance(radius, list) else radius
        if r == 0:
            out.append(p)
            continue
        a, b = poly[i - 1], poly[(i + 1) % len(poly)]
        u = _unit((a[0] - p[0], a[1] - p[1]))
        v = _unit((b[0] - p[0], b[1] - p[1]))
        half = math.acos(max(-1.0, min(1.0, u[0] * v[0] + u[1] * v[1]))) / 2
        d = r / math.tan(half)
        bis = _unit((u[0] + v[0], u[1] + v[1]))
        c = (p[0] + bis[0] * r / math.sin(half), p[1] + bis[1] * r / math.sin(half))
        t0 = math.atan2(p[1] + u[1] * d - c[1], p[0] + u[0] * d - c[0])
        t1 = math.atan2(p[1] + v[1] * d - c[1], p[0] + v[0] * d - c[0])
        sweep = (t1 - t0 + PI) % (2 * PI) - PI  # the short way round
        out += [(c[0] + r * math.cos(t0 + sweep * k / n), c[1] + r * math.sin(t0 + sweep * k / n))
                for k in range(n + 1)]
    return out


def _unit(v):
    length = math.hypot(*v)
    return (v[0] / length, v[1] / length)


def triangulate(poly):
    """Ear clipping of a simple counter-clockwise polygon: index triples, counter-clockwise."""
    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    idx, out = list(range(len(poly))), []
    while len(idx) > 3:
        for n in range(len(idx)):
            i, j, k = idx[n - 1], idx[n], idx[(n + 1) % len(idx)]
            a, b, c = poly[i], poly[j], poly[k]
            if cross(a, b, c) <= 1e-14:
                continue
            if any(cross(a, b, poly[m]) >= 0 and cross(b, c, poly[m]) >= 0 and cross(c, a, poly[m]) >= 0
                   for m in idx if m not in (i, j, k)):
                continue
            out.append((i, j, k))
            del idx[n]
            break
        else:
            raise ValueError("polygon is not simple and counter-clockwise")
    return out + [tuple(idx)]

# ---------------------------------------------------------------- 3D mesh builders


def lathe(profile, seg=SEG):
    """Solid of revolution about z. profile: (r, z) points, counter-clockwise in the (r, z)
    half-plane, starting and ending on the axis (r = 0)."""
    pts = [p for i, p in enumerate(profile) if i == 0 or math.dist(p, profile[i - 1]) > 1e-9]
    verts, tris, rings = [], [], []
    for r, z in pts:
        if r < 1e-9:
            rings.append([len(verts)])
            verts.append((0.0, 0.0, z))
        else:
            rings.append(list(range(len(verts), len(verts) + seg)))
            verts += [(r * math.cos(2 * PI * j / seg), r * math.sin(2 * PI * j / seg), z) for j in range(seg)]
    for a, b in zip(rings, rings[1:]):
        for j in range(seg):
            k = (j + 1) % seg
            if len(a) == 1:
                tris.append((a[0], b[k], b[j]))
            elif len(b) == 1:
                tris.append((a[j], a[k], b[0]))
            else:
                tris += [(a[j], a[k], b[k]), (a[j], b[k], b[j])]
    return verts, tris


def extrude(poly, w0, w1, layers):
    """Prism over a counter-clockwise polygon in the (x, z) plane, spanning y from -w1 to -w0.
    (Built as (u, v, w) -> (u, -w, v), a proper rotation, so orientation is kept.)"""
    n = len(poly)
    verts = [(u, -(w0 + (w1 - w0) * k / layers), v) for k in range(layers + 1) for (u, v) in poly]
    tris = []
    for k in range(layers):
        for i in range(n):
            a, b = k * n + i, k * n + (i + 1) % n
            tris += [(a, b, b + n), (a, b + n, a + n)]
    for i, j, k in triangulate(poly):
        tris += [(i, k, j), (layers * n + i, layers * n + j, layers * n + k)]
    return verts, tris


def transform(mesh, f):
    """Apply an orientation-preserving map to every vertex."""
    return [f(p) for p in mesh[0]], mesh[1]


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    return tuple(x / length for x in n)

# ---------------------------------------------------------------- writers, one per format


def fmt(x, places=6):
    s = f"{x:.{places}f}"
    return "0" if float(s) == 0 else s.rstrip("0").rstrip(".")


def file_verts(mesh, to_file, places):
    """Vertices in file coordinates, rounded once so every writer sees the same numbers."""
    return [tuple(round(c, places) + 0.0 for c in to_file(p)) for p in mesh[0]]


def write_stl_binary(path, mesh, to_file=lambda p: p):
    v = file_verts(mesh, to_file, 6)
    header = f"demo_arm {path.stem}: binary STL from scripts/make_demo_robot.py".encode().ljust(80)
    out = [header, struct.pack("<I", len(mesh[1]))]
    for t in mesh[1]:
        a, b, c = (v[i] for i in t)
        out.append(struct.pack("<12fH", *normal(a, b, c), *a, *b, *c, 0))
    path.write_bytes(b"".join(out))


def write_stl_ascii(path, mesh, to_file=lambda p: p):
    v = file_verts(mesh, to_file, 6)
    out = [f"solid {path.stem}"]
    for t in mesh[1]:
        out.append("  facet normal " + " ".join(f"{x:.6f}" for x in normal(*(v[i] for i in t))))
        out.append("    outer loop")
        out += ["      vertex " + " ".join(fmt(x) for x in v[i]) for i in t]
        out += ["    endloop", "  endfacet"]
    path.write_text("\n".join(out + [f"endsolid {path.stem}", ""]))


def write_obj(path, mesh, to_file=lambda p: p):
    v = file_verts(mesh, to_file, 6)
    out = [f"# demo_arm {path.stem}: Wavefront OBJ from scripts/make_demo_robot.py",
           f"# {len(v)} vertices, {len(mesh[1])} triangles", f"o {path.stem}"]
    out += ["v " + " ".join(fmt(x) for x in p) for p in v]
    out += ["f " + " ".join(str(i + 1) for i in t) for t in mesh[1]]
    path.write_text("\n".join(out) + "\n")


def write_dae(path, mesh, unit=1.0, up="Z_UP", matrix=None):
    """COLLADA 1.4.1. The consumers (MoveIt, Pinocchio: Assimp with its root node reset) map a file
    vertex v to matrix @ v, ignoring <unit> and <up_axis>, so the file stores v = matrix^-1 p; `unit`
    and `up` are only declared. matrix: 4x4 rows, translation in metres."""
    m = matrix or [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]

    def to_file(p):
        q = [c - m[i][3] for i, c in enumerate(p)]
        return tuple(sum(m[r][i] * q[r] for r in range(3)) for i in range(3))  # R^T q

    places = 6
    v = file_verts(mesh, to_file, places)
    name, tris = path.stem, mesh[1]
    pos = " ".join(fmt(x, places) for p in v for x in p)
    nrm = " ".join(f"{x:.6f}".rstrip("0").rstrip(".") for t in tris for x in normal(*(v[i] for i in t)))
    idx = " ".join(f"{i} {k}" for k, t in enumerate(tris) for i in t)
    unit_name = {1.0: "meter", 0.001: "millimeter"}[unit]
    mat = "\n".join(" ".join(fmt(x) for x in row) for row in m)

    def source(kind, data, count):
        return f"""        <source id="{name}-{kind}">
          <float_array id="{name}-{kind}-array" count="{3 * count}">{data}</float_array>
          <technique_common>
            <accessor source="#{name}-{kind}-array" count="{count}" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>"""
    path.write_text(f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>
    <contributor><authoring_tool>scm scripts/make_demo_robot.py</authoring_tool></contributor>
    <unit name="{unit_name}" meter="{fmt(unit)}"/>
    <up_axis>{up}</up_axis>
  </asset>
  <library_geometries>
    <geometry id="{name}-mesh" name="{name}">
      <mesh>
{source("positions", pos, len(v))}
{source("normals", nrm, len(tris))}
        <vertices id="{name}-vertices"><input semantic="POSITION" source="#{name}-positions"/></vertices>
        <triangles count="{len(tris)}">
          <input semantic="VERTEX" source="#{name}-vertices" offset="0"/>
          <input semantic="NORMAL" source="#{name}-normals" offset="1"/>
          <p>{idx}</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="{name}-node" name="{name}" type="NODE">
        <matrix sid="transform">{mat}</matrix>
        <instance_geometry url="#{name}-mesh" name="{name}"/>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
""")

# ---------------------------------------------------------------- the link shapes


def base_mesh():  # pedestal: foot flange, concave cove, tapered column up to joint1 at z = 0.12
    return lathe([(0.0, 0.0)] + arc(0.10, 0.01, 0.01, -90, 0, 4) + arc(0.11, 0.055, 0.025, -90, -180, 6)
                 + [(0.08, 0.11)] + arc(0.07, 0.11, 0.01, 0, 90, 4) + [(0.0, 0.12)])


def link1_mesh():  # shoulder column, dome centred on joint2 (z = 0.213)
    return lathe([(0.0, 0.0)] + arc(0.065, 0.005, 0.005, -90, 0, 3)
                 + [(0.07, 0.02), (0.066, 0.04)] + arc(0.0, 0.213, 0.065, 0, 90, 10))


def link2_mesh():  # shoulder hub around joint2's axis (y), y in [-0.07, 0.09]: plain, convex
    return transform(lathe(rounded_profile(-0.07, 0.09, 0.065, 0.065, 0.012, 5)), lambda p: (p[0], p[2], -p[1]))


def link3_mesh():  # upper-arm tube, tapering from r 0.06 to r 0.055
    return lathe(rounded_profile(0.04, 0.30, 0.06, 0.055, 0.012, 5), seg=40)


def link4_mesh():  # L-shaped elbow bracket: hub round joint4, a leg up to joint5 at (-0.0825, 0.14)
    top = math.degrees(math.acos(-0.035 / 0.055))  # where the hub circle meets the leg's inner face
    outline = arc(0.0, 0.0, 0.055, -90, top, 20) + [(-0.035, 0.14), (-0.13, 0.14), (-0.13, -0.055)]
    return extrude(round_corners(outline, [0] * 21 + [0.008] * 3, 4), -0.05, 0.05, 8)


def link5_mesh():  # forearm tube from joint5 towards joint6
    return lathe(rounded_profile(-0.01, 0.20, 0.055, 0.048, 0.01, 5))


def link6_mesh():  # wrist hub, along z here (the <collision> origin turns it onto y)
    return lathe(rounded_profile(-0.055, 0.07, 0.05, 0.05, 0.01, 5))


def hand_mesh():  # U-shaped palm: fingers slide along x in the slot x in [-0.075, 0.075], z > 0.03
    palm = [(-0.1, 0.0), (0.1, 0.0), (0.1, 0.065), (0.075, 0.065), (0.075, 0.03), (-0.075, 0.03),
            (-0.075, 0.065), (-0.1, 0.065)]
    return extrude(round_corners(palm, 0.006, 4), -0.03, 0.03, 8)


def finger_mesh():  # left finger; pad face at x = -0.001 (1 mm past the centre when closed)
    return extrude(round_corners([(-0.001, 0.002), (0.02, 0.002), (0.02, 0.035), (0.012, 0.085),
                                  (-0.001, 0.085)], 0.003, 5), -0.011, 0.011, 6)

# ---------------------------------------------------------------- the robot

ALONG_Y = (HALF_PI, 0, 0)  # rpy of a <collision> turning its z axis onto the link's y axis (z -> -y)
LINK4_MATRIX = [[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0.1], [0, 0, 0, 1]]  # +90 deg about x, 0.1 m up

# The "always" pair: shoulder_stop (fixed to link1) against link2's key plate; only joint 2 moves
# between them. The key is a flat plate tangent to the underside of link2's hub (bottom face at
# KEY_DEPTH below joint 2's axis, x in [-KEY_HALF, KEY_HALF]), reaching past the hub's +y end.
# The stop's top face lies STOP_GAP below it. Turning joint 2 by q lowers one end of the key to
# KEY_DEPTH cos q + KEY_HALF sin |q| below the axis, so the two overlap unless |q| < 0.0405 rad
# (97.7 % of joint 2's range [-1.76, 1.76]). Both sit at y >= 0.105, beyond link3's reach.
KEY_DEPTH, KEY_HALF, STOP_GAP = 0.065, 0.1, 0.004
KEY_Y, STOP_Y = (0.06, 0.135), (0.105, 0.135)  # y ranges (joint 2's axis is y)
KEY_THICK, STOP_THICK, STOP_HALF = 0.01, 0.02, 0.105

MESHES = {  # file -> (builder, writer, writer options); every builder returns element-frame metres
    "base.stl": (base_mesh, write_stl_binary, {}),
    "link1.obj": (link1_mesh, write_obj, {}),
    "link2.dae": (link2_mesh, write_dae, {}),
    "link3.stl": (link3_mesh, write_stl_ascii, {}),
    "link4.dae": (link4_mesh, write_dae, {"matrix": LINK4_MATRIX}),
    "link5.obj": (link5_mesh, write_obj, {"to_file": lambda p: (p[0], p[1], p[2] / 1.2)}),  # scale 1 1 1.2
    "link6.stl": (link6_mesh, write_stl_binary, {}),
    "hand.dae": (hand_mesh, write_dae, {}),
    "finger.stl": (finger_mesh, write_stl_ascii, {}),
}


def mesh(uri, xyz=(0, 0, 0), rpy=(0, 0, 0), scale=None):
    return ("mesh", uri, scale), xyz, rpy


def prim(kind, *dims, xyz=(0, 0, 0), rpy=(0, 0, 0)):
    return (kind, *dims), xyz, rpy


# name, mass (kg), visual material, collision elements (each also drawn as a visual)
LINKS = [
    ("base_link", 4.0, "demo_white", [mesh("meshes/base.stl"), prim("box", (0.26, 0.22, 0.012), xyz=(0, 0, 0.006))]),
    ("link1", 3.0, "demo_white", [mesh("package://demo_arm/meshes/link1.obj"),
                                  prim("cylinder", 0.05, 0.24, xyz=(0, 0, 0.213), rpy=ALONG_Y)]),
    ("link2", 2.0, "demo_grey", [mesh("meshes/link2.dae"),
                                 prim("box", (2 * KEY_HALF, KEY_Y[1] - KEY_Y[0], KEY_THICK),
                                      xyz=(0, sum(KEY_Y) / 2, -KEY_DEPTH + KEY_THICK / 2))]),
    ("link3", 2.5, "demo_white", [prim("sphere", 0.065), mesh("meshes/link3.stl"),
                                  prim("capsule", 0.055, 0.09, xyz=(0.0825, 0, 0.316), rpy=ALONG_Y)]),
    ("link4", 1.5, "demo_grey", [mesh("meshes/link4.dae")]),
    ("link5", 2.0, "demo_white", [mesh("meshes/link5.obj", scale=(1, 1, 1.2)),
                                  prim("box", (0.03, 0.05, 0.14), xyz=(-0.065, 0, 0.1))]),
    ("link6", 1.2, "demo_grey", [mesh("meshes/link6.stl", rpy=ALONG_Y),
                                 prim("cylinder", 0.04, 0.06, xyz=(0, 0, 0.04))]),
    ("link7", 0.5, "demo_black", [prim("cylinder", 0.045, 0.04, xyz=(0, 0, 0.02))]),
    ("link8", None, None, []),  # flange frame, no geometry
    ("hand", 0.7, "demo_orange", [mesh("meshes/hand.dae"), prim("cylinder", 0.04, 0.012, xyz=(0, 0, 0.004))]),
    ("finger_left", 0.02, "demo_black", [mesh("meshes/finger.stl")]),
    ("finger_right", 0.02, "demo_black", [mesh("meshes/finger.stl")]),
    ("camera_link", 0.1, "demo_black", [prim("box", (0.08, 0.025, 0.03))]),
    ("shoulder_stop", 0.1, "demo_black", [prim("box", (2 * STOP_HALF, STOP_Y[1] - STOP_Y[0], STOP_THICK))]),
]
COLORS = {"demo_white": "0.92 0.92 0.9 1", "demo_grey": "0.4 0.42 0.45 1", "demo_orange": "0.95 0.45 0.1 1",
          "demo_black": "0.08 0.08 0.08 1"}
TOP_LEVEL_MATERIAL = "demo_white"  # declared once at robot level, referenced by name; the others inline

ARM, WRIST = (87, 2.175), (12, 2.61)
# name, type, parent, child, origin xyz, origin rpy, axis (None: <axis/>), limit (lower, upper, effort, velocity)
JOINTS = [
    ("joint1", "revolute", "base_link", "link1", (0, 0, 0.12), (0, 0, 0), (0, 0, 1), (-2.9, 2.9, *ARM)),
    ("joint2", "revolute", "link1", "link2", (0, 0, 0.213), (0, 0, 0), (0, 1, 0), (-1.76, 1.76, *ARM)),
    ("shoulder_stop_joint", "fixed", "link1", "shoulder_stop",
     (0, sum(STOP_Y) / 2, 0.213 - KEY_DEPTH - STOP_GAP - STOP_THICK / 2), (0, 0, 0), None, None),
    ("joint3", "revolute", "link2", "link3", (0, 0, 0), (0, 0, 0), (0, 0, 1), (-2.9, 2.9, *ARM)),
    ("joint4", "revolute", "link3", "link4", (0.0825, 0, 0.316), (0, 0, 0), (0, 1, 0), (0.1, 3.4, *ARM)),
    ("joint5", "revolute", "link4", "link5", (-0.0825, 0, 0.14), (0, 0, 0), (0, 0, 1), (-2.9, 2.9, *WRIST)),
    ("joint6", "revolute", "link5", "link6", (0, 0, 0.244), (0, 0, 0), (0, 1, 0), (-2.6, 2.6, 12, None)),
    ("joint7", "continuous", "link6", "link7", (0, 0, 0.07), (0, 0, 0), (0, 0, 1), (None, None, *WRIST)),
    ("joint8", "fixed", "link7", "link8", (0, 0, 0.04), (0, 0, 0), None, None),
    ("hand_joint", "fixed", "link8", "hand", (0, 0, 0), (0, 0, 0), None, None),
    ("camera_joint", "fixed", "hand", "camera_link", (0, 0.04, 0.03), (0, 0, 0), None, None),
    ("finger_joint1", "prismatic", "hand", "finger_left", (0, 0, 0.03), (0, 0, 0), None, (0, 0.04, 20, 0.2)),
    ("finger_joint2", "prismatic", "hand", "finger_right", (0, 0, 0.03), (0, 0, PI), (1, 0, 0), (0, 0.04, 20, 0.2)),
]
MIMIC = {"finger_joint2": "finger_joint1"}


def num(x):
    return f"{x:.12g}"


def vec(v):
    return " ".join(num(x) for x in v)


def geometry_xml(g):
    kind = g[0]
    if kind == "mesh":
        scale = f' scale="{vec(g[2])}"' if g[2] else ""
        return f'<mesh filename="{g[1]}"{scale}/>'
    if kind == "box":
        return f'<box size="{vec(g[1])}"/>'
    if kind == "sphere":
        return f'<sphere radius="{num(g[1])}"/>'
    return f'<{kind} radius="{num(g[1])}" length="{num(g[2])}"/>'  # cylinder, capsule


def link_xml(name, mass, material, elements):
    if not elements:
        return [f'  <link name="{name}"/>']
    inertia = num(round(mass * 0.004, 6))
    out = [f'  <link name="{name}">', "    <inertial>", f'      <mass value="{num(mass)}"/>',
           f'      <inertia ixx="{inertia}" ixy="0" ixz="0" iyy="{inertia}" iyz="0" izz="{inertia}"/>',
           "    </inertial>"]
    mat = (f'<material name="{material}"/>' if material == TOP_LEVEL_MATERIAL else
           f'<material name="{material}"><color rgba="{COLORS[material]}"/></material>')
    for tag in ("visual", "collision"):
        for geom, xyz, rpy in elements:
            out += [f"    <{tag}>", f'      <origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>',
                    f"      <geometry>{geometry_xml(geom)}</geometry>"]
            out += [f"      {mat}"] if tag == "visual" else []
            out.append(f"    </{tag}>")
    return out + ["  </link>"]


def joint_xml(name, kind, parent, child, xyz, rpy, axis, limit):
    out = [f'  <joint name="{name}" type="{kind}">', f'    <parent link="{parent}"/>', f'    <child link="{child}"/>',
           f'    <origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>']
    if kind != "fixed":
        out.append(f'    <axis xyz="{vec(axis)}"/>' if axis else "    <axis/>  <!-- no xyz: defaults to 1 0 0 -->")
    if limit:
        attrs = zip(("lower", "upper", "effort", "velocity"), limit)
        out.append("    <limit " + " ".join(f'{k}="{num(v)}"' for k, v in attrs if v is not None) + "/>")
    if name in MIMIC:
        out.append(f'    <mimic joint="{MIMIC[name]}" multiplier="1" offset="0"/>')
    return out + ["  </joint>"]


def urdf_text():
    out = ['<?xml version="1.0"?>',
           "<!-- demo_arm: generated by scripts/make_demo_robot.py; edit the script, not this file. -->",
           '<robot name="demo_arm">',
           f'  <material name="{TOP_LEVEL_MATERIAL}"><color rgba="{COLORS[TOP_LEVEL_MATERIAL]}"/></material>']
    for link in LINKS:
        out += link_xml(*link)
    for joint in JOINTS:
        out += joint_xml(*joint)
    out += ["  <!-- ros2_control-style metadata: <joint> here names a joint, it is not a kinematic joint -->"]
    for j in ("joint1", "finger_joint1"):
        out += [f'  <transmission name="{j}_transmission">',
                "    <type>transmission_interface/SimpleTransmission</type>",
                f'    <joint name="{j}"><hardwareInterface>hardware_interface/PositionJointInterface'
                "</hardwareInterface></joint>",
                f'    <actuator name="{j}_motor"><mechanicalReduction>100</mechanicalReduction></actuator>',
                "  </transmission>"]
    out += ['  <gazebo reference="hand"><material>Gazebo/Orange</material><selfCollide>false</selfCollide></gazebo>',
            '  <gazebo><plugin name="demo_arm_control" filename="libgazebo_ros2_control.so">'
            "<parameters>demo_arm_controllers.yaml</parameters></plugin></gazebo>",
            "</robot>", ""]
    return "\n".join(out)


PACKAGE_XML = """<?xml version="1.0"?>
<!-- Only here so that package://demo_arm/... resolves to this folder. -->
<package format="3">
  <name>demo_arm</name>
  <version>0.1.0</version>
  <description>Demo 7-DOF arm with gripper for scm, generated by scripts/make_demo_robot.py.</description>
  <maintainer email="scm@example.com">scm developers</maintainer>
  <license>Apache-2.0</license>
</package>
"""

def geometry_md(geom, xyz, rpy):
    g = geometry_xml(geom)[1:-2].replace('filename="', "").replace('"', "")
    pose = (f" at xyz ({vec(xyz)})" if any(xyz) else "") + (f" rpy ({vec(rpy)})" if any(rpy) else "")
    return f"`{g}`{pose}"


def readme_text():
    links = ["| link | shape | collision elements (each also a visual) |", "| --- | --- | --- |"]
    links += [f"| {name} | {SHAPES[name]} | " + ("<br>".join(geometry_md(*e) for e in elements) or "none") + " |"
              for name, _, _, elements in LINKS]
    joints = ["| joint | type | parent → child | origin xyz (rpy) | axis | lower, upper |",
              "| --- | --- | --- | --- | --- | --- |"]
    for name, kind, parent, child, xyz, rpy, axis, limit in JOINTS:
        origin = vec(xyz) + (f" ({vec(rpy)})" if any(rpy) else "")
        ax = vec(axis) if axis else "`<axis/>` → 1 0 0" if kind != "fixed" else ""
        lim = f"{num(limit[0])}, {num(limit[1])}" if limit and limit[0] is not None else ""
        lim += f" (mimics {MIMIC[name]})" if name in MIMIC else " (no velocity)" if limit and limit[3] is None else ""
        joints.append(f"| {name} | {kind} | {parent} → {child} | {origin} | {ax} | {lim} |")
    return README.format(links="\n".join(links), joints="\n".join(joints))


SHAPES = {
    "base_link": "pedestal of revolution, r 0.11 at the floor to 0.07 at the top (z 0.12), on a foot plate",
    "link1": "column r 0.066-0.07 ending in a dome r 0.065 round C (z 0.213); motor cap r 0.05 along y through C",
    "link2": "shoulder hub r 0.065 round joint 2's axis, y in [-0.07, 0.09]; key plate under it, flat face "
             "0.065 below the axis, x in [-0.1, 0.1], y in [0.06, 0.135]",
    "link3": "shoulder sphere r 0.065 at C; tube r 0.06-0.055, z 0.04-0.30; elbow capsule r 0.055 along y at joint 4",
    "link4": "L-shaped elbow bracket, 0.1 thick in y: hub r 0.055 round joint 4, leg x in [-0.13, -0.035] "
             "up to joint 5",
    "link5": "forearm tube r 0.055-0.048, z -0.01-0.20; cable duct on -x",
    "link6": "wrist hub r 0.05 along y, y in [-0.07, 0.055]; neck r 0.04 up to joint 7",
    "link7": "flange disc r 0.045, 0.04 thick",
    "link8": "flange frame (like Panda's link8)",
    "hand": "U-shaped palm 0.2 (x) by 0.06 (y) by 0.065 (z), slot x in [-0.075, 0.075] above z 0.03; mounting plate",
    "finger_left": "finger 0.021 (x) by 0.022 (y) by 0.083 (z), pad face at x = -0.001",
    "finger_right": "the same finger, turned by the joint's yaw",
    "camera_link": "camera box on the hand's +y side",
    "shoulder_stop": "stop block beside link1's column, under link2's key plate: x in [-0.105, 0.105], "
                     "y in [0.105, 0.135], top face 0.069 below C (4 mm under the key at home)",
}

README = """# demo_arm: the scm demo robot

Generated by `scripts/make_demo_robot.py`; do not edit by hand. Regenerate and check with

    python3 scripts/make_demo_robot.py      # writes robots/demo_arm/ (deterministic)
    python3 scripts/check_demo_robot.py     # meshes parse and are closed, the tree is sound

Everything here (URDF, meshes, package.xml) is written by that script: no third-party files.

## The robot

A Panda-sized 7-DOF arm with a parallel two-finger gripper, 14 links (13 with geometry). Let C be
the centre of joint 2, 0.333 m above the floor. The upper arm is 0.316 m (C to joint 4, plus a
0.0825 m elbow offset along x), the forearm 0.384 m (joint 4 to joint 6, offset back by 0.0825 m),
then 0.11 m to the flange (link8) and 0.115 m more to the fingertips: 0.81 m from C to the flange.
Revolute axes are z or y of the parent frame, offsets are along z or x, all joint rpy are 0 except
the right finger's (yaw π). Fingers slide along the hand's x axis. Under the shoulder, a key plate
on link2 and a stop block fixed to link1 (its own link, shoulder_stop) line up only when joint 2 is
within 0.04 rad of 0: the designed "always" pair (see below).

Home, as used for the "default" category: every joint at 0, except joint4 whose range [0.1, 3.4]
excludes 0, so it sits at the middle, 1.75 rad (the forearm points forward, 10° below horizontal).

{links}

{joints}

Lengths are metres, angles radians. Capsule `length` is the cylindrical part (axis z, like a
cylinder): the link3 capsule spans y ∈ [-0.1, 0.1].

## Expected self-collision matrix

Measured with scm itself on the whole-link convex hulls (`scm sample -n 20000 --types hull`, seed
0: uniform samples, joint7 in [-π, π], the right finger mimicking the left). Fractions are of those
20 000 samples; "gap" is the hull type's `d_min` (sampling, plus scm's targeted search for pairs
closer than 2 cm). A hull fills concavities, so a gap between the hulls can be smaller than the
one between the meshes. 13 links with geometry make 78 pairs:

| reason | pairs | which |
| --- | --- | --- |
| same-link | 0 | none with one hull per link; two pieces of one link on the convex-piece types (73 pairs on decomp-hull) |
| adjacent | 12 | joined by a joint, or through the geometry-less link8 (link7-hand) |
| default | 2 | link1-link3 (in collision in every sample, home included), finger_left-finger_right |
| always | 1 | link2-shoulder_stop: 97.9 % of samples, 4 mm apart at home |
| never | 23 | listed below with their gaps |
| checked | 40 | everything else, in collision in 0.18 % to 28 % of samples |

The reasons are tried in MoveIt's order, the first that applies wins: same link, adjacent, default
(in collision at home), always (in collision in at least 95 % of samples), never. So a pair that
collides everywhere, home included, is **default**, not always.

**Adjacent** (12): base_link-link1, link1-link2, link1-shoulder_stop, link2-link3, link3-link4,
link4-link5, link5-link6, link6-link7, link7-hand, hand-finger_left, hand-finger_right,
hand-camera_link. link7 and hand are joined through link8, which has no geometry: adjacent by
MoveIt's rule (rigidly fixed, the hand's mounting plate, z ∈ [-0.002, 0.01], overlaps the flange
cylinder by 2 mm; without the rule they would be default).

**Always** (1): link2-shoulder_stop, designed for it. Only joint 2 moves between them (the stop is
fixed to link1, the key plate is part of link2; they are not adjacent: their path runs through
link1 and joint 2). The key's underside is flat, tangent to the hub at 0.065 below joint 2's axis,
and 0.2 wide (x ∈ [-0.1, 0.1]); the stop's top face is 0.069 below the axis, across x ∈ [-0.105,
0.105], and both overlap over y ∈ [0.105, 0.135]. Turning joint 2 by q lowers one end of the key to
0.065 cos q + 0.1 sin |q| below the axis, which passes 0.069 at |q| = 0.0405 rad: the two are apart
only for |q2| < 0.0405, 2.3 % of joint 2's range [-1.76, 1.76], and overlap everywhere else (at
q2 = ±1.76 the key's end still reaches 0.086 below the axis). Measured: 19 579 of 20 000 samples
(97.9 %) collide, home gap 0.004, deepest overlap 0.030 (the key's corners, 0.119 from the axis,
past the stop's bottom at 0.089). The stop and the key's overhang sit at y ≥ 0.105, beyond link3
(|y| ≤ 0.065 near the shoulder): the stop never touches the upper arm (gap 0.015 on the hulls).

**Default** (2):
- link1-link3, in collision in every sample (100 %) but also at home. Joint 3's axis passes
  through C, so C is a fixed point of link1, link2 and link3 at once. link1's dome (r 0.065) and
  motor cap (r 0.05) contain C, and so does link3's shoulder sphere (r 0.065): the two share a
  ball of radius 0.05 round C in every configuration, although joint 2 and joint 3 both move
  between them. This is why the always pair above needed a gap at home.
- finger_left-finger_right. Each pad face is at x = -0.001 in its finger's frame and the right
  frame is yawed by π, so at finger_joint1 = 0 (home; 0 is inside [0, 0.04]) the pads overlap by
  2 mm. They part once the opening exceeds 1 mm: 2.6 % of samples collide.

**Never** (23), with the gap:
- base_link-link2 (0.094): joint 2 spins link2 about its own axis; its lowest points are the key's
  corners, sqrt(0.1² + 0.065²) = 0.119 from C: 0.333 - 0.119 = 0.214 above the floor, the base is
  0.12 tall.
- base_link-link3 (0.094): joint 2 tilts the upper arm at most 1.76 rad (10.8° below horizontal);
  the lowest link3's meshes get is the elbow capsule at 0.333 + 0.316 cos 1.76 - 0.0825 sin 1.76 -
  0.055 = 0.138 above the floor (the hulls, widened by the base's foot plate and link3's
  sphere-to-capsule cone, come to 0.094).
- base_link-link4 (0.025), link1-link4 (0.055), link2-link4 (0.103): the elbow bracket stays
  within 0.2 of joint 4, which stays 0.327 from C and above z = 0.19.
- base_link-shoulder_stop (0.128): only joint 1 moves between them; the stop is 0.244 to 0.264
  above the floor, beside the column (y ≥ 0.105), the base 0.12 tall.
- link3-shoulder_stop (0.015): link3 reaches |y| ≤ 0.065 near C; only its hull, widening towards
  the elbow capsule (|y| ≤ 0.1), comes this close, with joint 2 at its limit.
- link4-shoulder_stop (0.040): the stop hangs under the shoulder, where the elbow bracket does
  not get.
- link4-link6 (0.163), link4-link7 (0.127), link4-hand (0.042), link4-finger_left (0.033),
  link4-finger_right (0.030), link4-camera_link (0.077): the forearm keeps the wrist 0.384 from
  joint 4, and folding joint 6 back (±2.6) brings the hand over the forearm, not the elbow.
- link6-hand (0.038), link6-finger_left (0.072), link6-finger_right (0.072), link6-camera_link
  (0.055): only joint 7 (about the flange axis) moves between them; link6's neck ends at joint 7,
  0.04 below the flange, the hand starts 0.002 below the flange.
- link7-finger_left, link7-finger_right (0.032): the fingers start 0.032 above the flange and only
  slide along x. link7-camera_link (0.015): rigidly fixed, the camera starts 0.015 above the flange.
- finger_left-camera_link, finger_right-camera_link (0.0165): the camera is at y ≥ 0.0275 of the
  hand, the fingers at |y| ≤ 0.011, and they only move along x.

**Checked** (40), in collision in some samples only: every pair of {{base_link, link1, link2,
link3, shoulder_stop}} × {{link5, link6, link7, hand, finger_left, finger_right, camera_link}} (35),
and link5 × {{link7, hand, finger_left, finger_right, camera_link}} (5). Three wide ranges make the
arm reach itself: joint 2 (±1.76) tilts the upper arm below horizontal, joint 4 (up to 3.4) folds
the forearm back past parallel, joint 6 (±2.6) folds the hand back onto the forearm.
Configurations to check by hand (joints 1..7, fingers closed, others 0):
- q4 = π: the forearm hangs parallel to the upper arm, its axis 2 × 0.0825 = 0.165 in front:
  joint 6 at (0.165, 0, 0.265), the flange at z 0.155, the hand pointing down. With q7 = 0 the
  palm (0.2 long along the hand's x) spans x ∈ [0.065, 0.265], z ∈ [0.09, 0.155]: it hits the
  base pedestal (r 0.08 there) and link1's column (r 0.07): base_link-hand, link1-hand. With
  q7 = π/2 the palm spans x ∈ [0.135, 0.195] only: no collision.
- q4 ≥ 3.32 (3.22 with q5 = π, the cable duct turned inwards): the forearm swings past parallel
  into the upper arm: link3-link5 (8.5 % of samples on the hulls), then link2-link5, link1-link5,
  link3-link6...
- q2 = 1.0, q4 = 2.8: the upper arm leans forward, the folded forearm brings the wrist down onto
  the base: base_link-link6, base_link-link7, base_link-hand, base_link-camera_link.
- q4 = 1.75, q6 = 2.6: the hand folds back onto the forearm: link5-link7, link5-hand,
  link5-camera_link.
- q4 = 3.0, q6 = 2.6: folded elbow and wrist put the hand on the shoulder: link1-hand, link2-hand,
  link3-hand. A folded elbow (q4 ≈ 3.2) with the upper arm tilted (|q2| ≈ 1.3 to 1.6) brings the
  forearm and wrist under the shoulder: link6-shoulder_stop (3.4 %), link5-shoulder_stop (1.9 %).

Least frequent: finger_right-shoulder_stop 0.18 %, finger_left-shoulder_stop 0.22 %,
camera_link-shoulder_stop 0.34 %, base_link-link5 0.78 %, link3-finger_left/right 0.8 %;
everything else is above 1 %, up to link5-link7 at 28 %. A matrix built from fewer than a few
thousand samples may call the rarest of these "never".

Other shape types (same run, all six types): one oriented box per link (obb) gives the same
matrix except base_link-link4 (0.03 %) and link3-shoulder_stop (36 %), which become checked. One
bounding sphere per link coarsens it: link6-hand, link7-camera_link, both finger-camera pairs and
base_link-shoulder_stop overlap at home (default), so do link2-shoulder_stop and
link3-shoulder_stop (default); base_link-link3, link1-link4 and link4-hand become checked
(base_link-link4 and the link4-finger pairs rarely, 0.03 to 0.09 %). On convex pieces
(decomp-hull, decomp-obb) the always pair is the key's piece against the stop; the hub's pieces
never reach it.

## What the files exercise

- `base.stl`, `link6.stl`: binary STL (header does not start with "solid"). `link6.stl` is
  authored along z and laid along y by its `<collision>` rpy (π/2, 0, 0); it is longer on -y.
- `link3.stl`, `finger.stl`: ASCII STL. `finger.stl` serves both fingers; the right one is
  mirrored by its joint's yaw π and moves through the mimic joint.
- `link1.obj`: Wavefront OBJ, referenced as `package://demo_arm/meshes/link1.obj`; `package.xml`
  in this folder names the package `demo_arm`. All other meshes use relative paths.
- `link5.obj`: OBJ with `scale="1 1 1.2"`: the file stops at z = 0.167, scaled at 0.20, where it
  overlaps link6's hub; unscaled, the forearm would float 2.7 cm short of the wrist.
- `link2.dae`, `link4.dae`, `hand.dae`: COLLADA in metres, Z_UP, as MoveIt and Pinocchio read
  it: they ignore `<unit>` and `<up_axis>` (Assimp puts both on the root node, which they reset),
  so a demo that declared others would be checked in a different geometry than it shows. In
  link2's frame the hub lies along y over y ∈ [-0.07, 0.09].
- `link4.dae`: its triangles sit under a node `<matrix>`: +90° about x and a 0.1 m translation. A
  vertex v maps to R v + t: the L-bracket lands at x ∈ [-0.13, 0.055], z ∈ [-0.055, 0.14].
  Ignoring the matrix puts it in the wrong plane and 0.1 m off.
- `hand.dae`: identity matrix, and the clearly non-convex link (a
  U-shaped palm: mesh volume / hull volume 0.6). link4's L is mildly non-convex (0.91); link2,
  link3, link5 and link6 are convex bodies of revolution.
- Every DAE stores per-triangle normals as a second `<input>` (offset 1), so `<p>` interleaves
  vertex and normal indices.
- All meshes are closed and outward-oriented (every edge in exactly two triangles, opposite
  directions); 416 to 1 632 triangles each.
- URDF leniency: a `<limit>` without `velocity` (joint6), an `<axis/>` without `xyz`
  (finger_joint1, meant to be x), `<transmission>` blocks whose `<joint>` children are not
  kinematic joints, `<gazebo>` blocks, `<inertial>`s, one top-level `<material>` referenced by
  name and inline ones in visuals, a `<capsule>`, several `<collision>`s per link with their own
  origins, a fixed joint to a link with no geometry (link8) and two to links with geometry
  (camera_link, shoulder_stop).
"""


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "robots" / "demo_arm"
    (out / "meshes").mkdir(parents=True, exist_ok=True)
    for file, (build, write, options) in MESHES.items():
        write(out / "meshes" / file, build(), **options)
    (out / "demo_arm.urdf").write_text(urdf_text())
    (out / "package.xml").write_text(PACKAGE_XML)
    (out / "README.md").write_text(readme_text())
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
