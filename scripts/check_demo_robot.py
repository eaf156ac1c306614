#!/usr/bin/env python3
"""Check a URDF and its meshes (made for robots/demo_arm; standard library only).

    python3 scripts/check_demo_robot.py [URDF]     # default: robots/demo_arm/demo_arm.urdf

Checks: every joint's parent and child exist, each link has at most one parent, there is a
single root; every mesh file resolves (relative path or package://) and parses (binary or
ASCII STL, OBJ, COLLADA with node <matrix>, its <unit> and <up_axis> ignored as MoveIt and
Pinocchio ignore them); every mesh is closed (each
edge shared by exactly two triangles), consistently oriented and encloses a positive volume.
Prints per link its collision elements and triangles. Exits 1 on any failure.
"""
import math
import struct
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

# ---------------------------------------------------------------- mesh readers -> (vertices, triangles)


def read_stl(data):
    if data.lstrip()[:5].lower() == b"solid":
        try:
            return read_stl_ascii(data.decode("ascii"))
        except (UnicodeDecodeError, ValueError):
            pass  # a binary STL whose header happens to start with "solid"
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * count:
        raise ValueError(f"binary STL: {len(data)} bytes for {count} triangles")
    flat = [struct.unpack_from("<9f", data, 84 + 50 * i + 12) for i in range(count)]
    return weld([f[k:k + 3] for f in flat for k in (0, 3, 6)])


def read_stl_ascii(text):
    words = text.split()
    if "facet" not in words:
        raise ValueError("ASCII STL without facets")
    points = [tuple(float(x) for x in words[i + 1:i + 4]) for i, w in enumerate(words) if w == "vertex"]
    if len(points) % 3:
        raise ValueError("ASCII STL: vertex count is not a multiple of 3")
    return weld(points)


def weld(points):
    """Triangle soup (3 points per triangle) -> indexed mesh, merging identical coordinates."""
    index, verts, tris = {}, [], []
    for p in points:
        if p not in index:
            index[p] = len(verts)
            verts.append(p)
    ids = [index[p] for p in points]
    tris = [tuple(ids[i:i + 3]) for i in range(0, len(ids), 3)]
    return verts, tris


def read_obj(text):
    verts, tris = [], []
    for line in text.splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append(tuple(float(x) for x in parts[1:4]))
        elif parts[0] == "f":
            ids = [int(p.split("/")[0]) for p in parts[1:]]
            ids = [i - 1 if i > 0 else len(verts) + i for i in ids]
            tris += [(ids[0], ids[k], ids[k + 1]) for k in range(1, len(ids) - 1)]
    return verts, tris


def read_dae(text):
    """COLLADA: every <instance_geometry> of the scene, through its node <matrix> chain. <unit meter>
    and <up_axis> are ignored, as MoveIt and Pinocchio ignore them (Assimp puts both on the root
    node, which they reset)."""
    root = ET.fromstring(text)
    ns = root.tag.split("}")[0] + "}" if root.tag.startswith("{") else ""
    by_id = {el.get("id"): el for el in root.iter() if el.get("id")}
    verts, tris = [], []

    def visit(node, m):
        for mat in node.findall(f"{ns}matrix"):
            m = matmul(m, [[float(x) for x in mat.text.split()][4 * r:4 * r + 4] for r in range(4)])
        if node.findall(f"{ns}translate") or node.findall(f"{ns}rotate") or node.findall(f"{ns}scale"):
            raise ValueError("COLLADA: only <matrix> node transforms are supported here")
        for inst in node.findall(f"{ns}instance_geometry"):
            v, t = dae_geometry(by_id[inst.get("url")[1:]], ns, by_id)
            base = len(verts)
            verts.extend(apply(m, p) for p in v)
            tris.extend(tuple(base + i for i in tri) for tri in t)
        for child in node.findall(f"{ns}node"):
            visit(child, m)

    scene_url = root.find(f"{ns}scene/{ns}instance_visual_scene").get("url")[1:]
    visit(by_id[scene_url], [[1.0 if r == c else 0.0 for c in range(4)] for r in range(4)])
    return verts, tris


def dae_geometry(geometry, ns, by_id):
    mesh = geometry.find(f"{ns}mesh")
    verts, tris = [], []
    for prims in list(mesh.findall(f"{ns}triangles")) + list(mesh.findall(f"{ns}polylist")):
        inputs = prims.findall(f"{ns}input")
        stride = 1 + max(int(i.get("offset", "0")) for i in inputs)
        vin = next(i for i in inputs if i.get("semantic") == "VERTEX")
        pos_src = by_id[vin.get("source")[1:]].find(f"{ns}input[@semantic='POSITION']").get("source")[1:]
        floats = [float(x) for x in by_id[pos_src].find(f"{ns}float_array").text.split()]
        points = [tuple(floats[k:k + 3]) for k in range(0, len(floats), 3)]
        p = [int(x) for x in prims.find(f"{ns}p").text.split()][int(vin.get("offset", "0"))::stride]
        counts = ([int(x) for x in prims.find(f"{ns}vcount").text.split()] if prims.tag.endswith("polylist")
                  else [3] * (len(p) // 3))
        base, k = len(verts), 0
        verts.extend(points)
        for c in counts:
            tris += [(base + p[k], base + p[k + j], base + p[k + j + 1]) for j in range(1, c - 1)]
            k += c
    return verts, tris



def matmul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def apply(m, p):
    return tuple(m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3] for r in range(3))


def load_mesh(path):
    suffix = path.suffix.lower()
    if suffix == ".stl":
        return read_stl(path.read_bytes())
    if suffix == ".obj":
        return read_obj(path.read_text())
    if suffix == ".dae":
        return read_dae(path.read_text())
    raise ValueError(f"unsupported mesh format {suffix}")

# ---------------------------------------------------------------- mesh checks


def closed_mesh_problems(verts, tris):
    """Problems with a triangle mesh as the boundary of a solid ([] when it is fine)."""
    key = {}
    canon = [key.setdefault(tuple(round(c, 9) for c in p), i) for i, p in enumerate(verts)]
    directed = {}
    for t in tris:
        a, b, c = (canon[i] for i in t)
        if len({a, b, c}) < 3:
            return ["degenerate triangle"]
        for e in ((a, b), (b, c), (c, a)):
            directed[e] = directed.get(e, 0) + 1
    problems = []
    undirected = {}
    for (a, b), n in directed.items():
        undirected[min(a, b), max(a, b)] = undirected.get((min(a, b), max(a, b)), 0) + n
    bad = sum(1 for n in undirected.values() if n != 2)
    if bad:
        problems.append(f"{bad} edges not shared by exactly two triangles")
    flipped = sum(1 for (a, b), n in directed.items() if n != 1 or directed.get((b, a)) != 1)
    if not bad and flipped:
        problems.append(f"{flipped} edges with inconsistent triangle orientation")
    volume = signed_volume(verts, tris)
    if volume <= 0:
        problems.append(f"signed volume {volume:.3g} <= 0 (inward-facing)")
    return problems


def signed_volume(verts, tris):
    total = 0.0
    for i, j, k in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[i], verts[j], verts[k]
        total += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    return total / 6

# ---------------------------------------------------------------- URDF


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def parse_origin(el):
    o = el.find("origin") if el is not None else None
    xyz = [float(x) for x in o.get("xyz", "0 0 0").split()] if o is not None else [0.0] * 3
    rpy = [float(x) for x in o.get("rpy", "0 0 0").split()] if o is not None else [0.0] * 3
    return xyz, rpy


def resolve(uri, urdf_path):
    if uri.startswith("package://"):
        package, _, rest = uri[len("package://"):].partition("/")
        for folder in [urdf_path.parent, *urdf_path.parent.parents]:
            for pkg in [folder / "package.xml", *folder.glob("*/package.xml")]:
                if pkg.is_file() and ET.parse(pkg).getroot().findtext("name", "").strip() == package:
                    return pkg.parent / rest
        raise FileNotFoundError(f"no package.xml named {package} above {urdf_path.parent}")
    if uri.startswith("file://"):
        return Path(uri[len("file://"):])
    return urdf_path.parent / uri


def collision_geometry(col, urdf_path):
    """One <collision>: (kind, detail, mesh in the link frame or None for a primitive)."""
    geom = list(col.find("geometry"))[0]
    xyz, rpy = parse_origin(col)
    rot = rpy_matrix(*rpy)
    if geom.tag != "mesh":
        return geom.tag, " ".join(f"{k}={v}" for k, v in geom.attrib.items()), None
    path = resolve(geom.get("filename"), urdf_path)
    scale = [float(x) for x in geom.get("scale", "1 1 1").split()]
    verts, tris = load_mesh(path)
    problems = closed_mesh_problems(verts, tris)
    if problems:
        raise ValueError(f"{path.name}: " + "; ".join(problems))
    link_verts = [tuple(sum(rot[r][c] * p[c] * scale[c] for c in range(3)) + xyz[r] for r in range(3))
                  for p in verts]
    return "mesh", path.name, (link_verts, tris)


def check(urdf_path):
    root = ET.parse(urdf_path).getroot()
    errors, links = [], {link.get("name"): link for link in root.findall("link")}
    parent_of = {}
    for joint in root.findall("joint"):  # direct children only: <transmission><joint> is not kinematic
        name, kind = joint.get("name"), joint.get("type")
        parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
        for link in (parent, child):
            if link not in links:
                errors.append(f"joint {name}: unknown link {link}")
        if child in parent_of:
            errors.append(f"link {child} has two parents")
        parent_of[child] = parent
        if kind in ("revolute", "prismatic") and joint.find("limit") is None:
            errors.append(f"joint {name}: {kind} without <limit>")
        mimic = joint.find("mimic")
        if mimic is not None and mimic.get("joint") not in {j.get("name") for j in root.findall("joint")}:
            errors.append(f"joint {name}: mimics unknown joint {mimic.get('joint')}")
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        errors.append(f"expected a single root link, found {roots}")
    print(f"{urdf_path}: {len(links)} links, {len(root.findall('joint'))} joints, root {roots}")
    total_tris = 0
    for name, link in links.items():
        parts, tris = [], 0
        for col in link.findall("collision"):
            try:
                kind, detail, m = collision_geometry(col, urdf_path)
            except (OSError, ValueError, KeyError, struct.error, ET.ParseError) as e:
                errors.append(f"link {name}: {e}")
                continue
            tris += len(m[1]) if m else 0
            parts.append(f"{detail} ({len(m[1])} tris)" if m else f"{kind} {detail}")
        total_tris += tris
        if link.findall("collision") and not link.findall("visual"):
            errors.append(f"link {name}: collision geometry but no visual")
        print(f"  {name:13} {len(parts)} collision, {tris:5} mesh triangles: " + ", ".join(parts))
    print(f"  total mesh triangles: {total_tris}")
    for e in errors:
        print(f"ERROR: {e}")
    print("OK" if not errors else f"FAILED: {len(errors)} problems")
    return not errors


if __name__ == "__main__":
    default = Path(__file__).resolve().parent.parent / "robots" / "demo_arm" / "demo_arm.urdf"
    sys.exit(0 if check(Path(sys.argv[1]) if len(sys.argv) > 1 else default) else 1)
