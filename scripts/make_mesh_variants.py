#!/usr/bin/env python3
"""Writes tests/data/mesh_variants/: a small authored robot whose collision meshes are written the way
real exporters write them, for the mesh-format tests and the geometry parity test against Pinocchio.

  base  binary STL whose 80-byte header begins with "solid"
  l1    ASCII STL with tabs, CRLF line ends, runs of spaces and blank lines
  l2    OBJ: quads, a pentagon, two objects, negative (relative) indices, v/vt/vn corners,
        a missing mtllib, point and line elements
  l3    COLLADA <polylist> declaring Y_UP and inches (both ignored by the consumers)
  l4    COLLADA <polygons>, <triangles> and <lines> in one mesh, under nested nodes with
        <matrix>, <translate>, <rotate> and <scale>
  l5    COLLADA <instance_node> from <library_nodes>, one geometry instanced twice, <tristrips>,
        <trifans>, and a geometry no node instances (not part of the scene)
  l6    an asymmetric OBJ mirrored by scale="1 -1 1", plus a box, a cylinder and a sphere
Also meshes/wrong_count.stl: a binary STL whose header says 0 triangles (Assimp refuses it; scm
reads it with a note), used only by the mesh-format tests.

Deterministic: rerunning rewrites the same bytes.
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "data", "mesh_variants")
MESHES = os.path.join(OUT, "meshes")


def box_triangles(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    tris = []
    for a, b, c, d in quads:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


def binary_stl(path, header, tris, declared=None):
    with open(path, "wb") as f:
        f.write(header.ljust(80, b" ")[:80])
        f.write(struct.pack("<I", len(tris) if declared is None else declared))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


def ascii_stl(path, tris):
    lines = ["  solid\tirregular  ", ""]
    for t in tris:
        lines.append("facet   normal 0 0 0")
        lines.append("\touter loop")
        for p in t:
            lines.append("\t\tvertex\t%s   %s %s" % tuple(repr(c) for c in p))
        lines.append("   endloop")
        lines.append("endfacet")
        lines.append("")
    lines.append("endsolid irregular")
    with open(path, "wb") as f:
        f.write("\r\n".join(lines).encode())


def obj_l2(path):
    # Object "prism": a pentagonal prism (two pentagons as n-gons, five quads), absolute indices.
    # Object "cube": a cube written with negative indices and v/vt/vn corners.
    out = ["# authored for scm's mesh tests", "mtllib missing.mtl", "o prism"]
    r, z0, z1 = 0.03, 0.0, 0.05
    for z in (z0, z1):
        for k in range(5):
            t = 2 * math.pi * k / 5
            out.append("v %.6f %.6f %.6f" % (r * math.cos(t), r * math.sin(t), z))
    out.append("f 5 4 3 2 1")
    out.append("f 6 7 8 9 10")
    for k in range(5):
        a, b = 1 + k, 1 + (k + 1) % 5
        out.append("f %d %d %d %d" % (a, b, b + 5, a + 5))
    out.append("p 1")
    out.append("l 1 6")
    out.append("o cube")
    out.append("vt 0 0")
    out.append("vn 0 0 1")
    cube = [(x, y, z) for z in (0.05, 0.08) for y in (-0.02, 0.02) for x in (-0.02, 0.02)]
    for p in cube:
        out.append("v %.6f %.6f %.6f" % p)
    # After the 8 cube vertices, vertex -8 is the cube's first.
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    for f in faces:
        out.append("f " + " ".join("%d/-1/-1" % (i - 8) for i in f))
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")


def obj_l6(path):
    # An asymmetric wedge: mirrored in y it is a different shape, so a wrong mirror is visible.
    v = [(0, 0, 0), (0.06, 0, 0), (0, 0.03, 0), (0, 0, 0.04)]
    f = [(1, 3, 2), (1, 2, 4), (1, 4, 3), (2, 3, 4)]
    with open(path, "w") as fh:
        fh.write("".join("v %s %s %s\n" % p for p in v))
        fh.write("".join("f %d %d %d\n" % t for t in f))


def floats(values):
    return " ".join("%.6g" % x for x in values)


def dae(asset, geometries, scene, library_nodes=""):
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>{asset}</asset>
  <library_geometries>
{geometries}
  </library_geometries>
{library_nodes}
  <library_visual_scenes>
    <visual_scene id="scene">
{scene}
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""


def geometry(gid, points, prims):
    n = len(points)
    flat = [c for p in points for c in p]
    return f"""    <geometry id="{gid}"><mesh>
      <source id="{gid}-pos"><float_array id="{gid}-arr" count="{3 * n}">{floats(flat)}</float_array>
        <technique_common><accessor source="#{gid}-arr" count="{n}" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <source id="{gid}-nrm"><float_array id="{gid}-narr" count="3">0 0 1</float_array>
        <technique_common><accessor source="#{gid}-narr" count="1" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="{gid}-vtx"><input semantic="POSITION" source="#{gid}-pos"/></vertices>
{prims}
    </mesh></geometry>"""


def inputs(gid):
    return (f'<input semantic="VERTEX" source="#{gid}-vtx" offset="0"/>'
            f'<input semantic="NORMAL" source="#{gid}-nrm" offset="1"/>')


def p(indices):
    """A <p> list with each position index followed by normal index 0 (two inputs, offsets 0 and 1)."""
    return " ".join("%d 0" % i for i in indices)


CUBE = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
CUBE_QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]


def scaled(points, s, offset=(0, 0, 0)):
    return [tuple(c * s + o for c, o in zip(pt, offset)) for pt in points]


def dae_l3():
    pts = scaled(CUBE, 0.04, (-0.02, -0.02, 0.0))
    prim = (f'      <polylist count="6">{inputs("l3")}<vcount>4 4 4 4 4 4</vcount>'
            f'<p>{p([i for q in CUBE_QUADS for i in q])}</p></polylist>')
    return dae('<unit name="inch" meter="0.0254"/><up_axis>Y_UP</up_axis>',
               geometry("l3", pts, prim),
               '      <node id="l3-node"><instance_geometry url="#l3"/></node>')


def dae_l4():
    # Two far positions that only the line uses: were lines counted, the box would grow to a metre.
    pts = scaled(CUBE, 0.03) + [(1.0, 1.0, 1.0), (-1.0, -1.0, -1.0)]
    quads = CUBE_QUADS[:3]
    tris = []
    for a, b, c, d in CUBE_QUADS[3:]:
        tris += [a, b, c, a, c, d]
    prims = (f'      <polygons count="3">{inputs("l4")}'
             + "".join(f"<p>{p(q)}</p>" for q in quads) + "</polygons>\n"
             f'      <triangles count="6">{inputs("l4")}<p>{p(tris)}</p></triangles>\n'
             # A line far outside the cube: consumers drop line primitives, so it must not count.
             f'      <lines count="1">{inputs("l4")}<p>{p([8, 9])}</p></lines>')
    scene = """      <node id="l4-outer"><translate>0.01 0 0.02</translate><rotate>0 0 1 30</rotate>
        <node id="l4-inner"><matrix>1 0 0 0  0 0 -1 0.01  0 1 0 0  0 0 0 1</matrix><scale>1 0.5 2</scale>
          <instance_geometry url="#l4"/>
        </node>
      </node>"""
    return dae('<unit name="meter" meter="1"/><up_axis>Z_UP</up_axis>',
               geometry("l4", pts, prims), scene)


def dae_l5():
    strip_pts = scaled(CUBE, 0.025)
    # The cube as two strips and two fans: strip around the four sides, fans for top and bottom.
    strip = [0, 4, 1, 5, 3, 7, 2, 6, 0, 4]
    prims = (f'      <tristrips count="1">{inputs("l5")}<p>{p(strip)}</p></tristrips>\n'
             f'      <trifans count="2">{inputs("l5")}<p>{p([0, 2, 3, 1])}</p><p>{p([4, 5, 7, 6])}</p></trifans>')
    unused = geometry("l5-unused", scaled(CUBE, 0.01, (5, 5, 5)),
                      f'      <triangles count="1">{inputs("l5-unused")}<p>{p([0, 1, 2])}</p></triangles>')
    library_nodes = """  <library_nodes>
    <node id="l5-part"><translate>0 0 0.03</translate><instance_geometry url="#l5"/></node>
  </library_nodes>"""
    scene = """      <node id="l5-a"><instance_geometry url="#l5"/></node>
      <node id="l5-b"><rotate>1 0 0 90</rotate><instance_node url="#l5-part"/></node>"""
    return dae('<unit meter="1"/><up_axis>Z_UP</up_axis>',
               geometry("l5", strip_pts, prims) + "\n" + unused, scene, library_nodes)


URDF = """<?xml version="1.0"?>
<!-- Authored for scm's tests by scripts/make_mesh_variants.py: each link's collision mesh is one way
     real exporters write mesh files. -->
<robot name="mesh_variants">
  <link name="base">
    <collision><geometry><mesh filename="package://mesh_variants/meshes/solid_header.stl"/></geometry></collision>
  </link>
  <link name="l1">
    <collision><origin xyz="0 0 0.01"/><geometry><mesh filename="package://mesh_variants/meshes/irregular.stl"/></geometry></collision>
  </link>
  <link name="l2">
    <collision><geometry><mesh filename="package://mesh_variants/meshes/polygons.obj"/></geometry></collision>
  </link>
  <link name="l3">
    <collision><origin xyz="0 0 0.01" rpy="0 0.3 0"/><geometry><mesh filename="package://mesh_variants/meshes/polylist_yup_inch.dae"/></geometry></collision>
  </link>
  <link name="l4">
    <collision><geometry><mesh filename="package://mesh_variants/meshes/nested_nodes.dae" scale="1.5 1 1"/></geometry></collision>
  </link>
  <link name="l5">
    <collision><geometry><mesh filename="package://mesh_variants/meshes/instances.dae"/></geometry></collision>
  </link>
  <link name="l6">
    <collision><geometry><mesh filename="package://mesh_variants/meshes/wedge.obj" scale="1 -1 1"/></geometry></collision>
    <collision><origin xyz="0.05 0 0.02" rpy="0.4 0 0.2"/><geometry><box size="0.02 0.03 0.01"/></geometry></collision>
    <collision><origin xyz="0 0.05 0.02" rpy="0 0.7 0"/><geometry><cylinder radius="0.01" length="0.04"/></geometry></collision>
    <collision><origin xyz="-0.04 0 0.03"/><geometry><sphere radius="0.012"/></geometry></collision>
  </link>
  <link name="tool">
    <visual><geometry><box size="0.02 0.02 0.02"/></geometry></visual>
  </link>
{joints}
</robot>
"""


def joints():
    chain = ["base", "l1", "l2", "l3", "l4", "l5", "l6", "tool"]
    axes = ["0 0 1", "0 1 0", "1 0 0", "0 1 0", "0 0 1", "1 0 0", "0 1 0"]
    out = []
    for k in range(len(chain) - 1):
        kind = "fixed" if chain[k + 1] == "tool" else ("continuous" if k == 0 else "revolute")
        limit = '<limit lower="-2.0" upper="2.0" effort="1" velocity="1"/>' if kind == "revolute" else ""
        axis = f'<axis xyz="{axes[k]}"/>' if kind != "fixed" else ""
        out.append(f'  <joint name="j{k + 1}" type="{kind}"><parent link="{chain[k]}"/>'
                   f'<child link="{chain[k + 1]}"/><origin xyz="0 0 0.09" rpy="0 0 0.2"/>{axis}{limit}</joint>')
    return "\n".join(out)


def main():
    os.makedirs(MESHES, exist_ok=True)
    binary_stl(os.path.join(MESHES, "solid_header.stl"), b"solid exported by a CAD tool",
               box_triangles((-0.04, -0.04, 0.0), (0.04, 0.04, 0.06)))
    binary_stl(os.path.join(MESHES, "wrong_count.stl"), b"binary, count not filled in",
               box_triangles((0, 0, 0), (0.01, 0.02, 0.03)), declared=0)
    ascii_stl(os.path.join(MESHES, "irregular.stl"), box_triangles((-0.03, -0.02, 0.0), (0.03, 0.02, 0.07)))
    obj_l2(os.path.join(MESHES, "polygons.obj"))
    obj_l6(os.path.join(MESHES, "wedge.obj"))
    for name, text in [("polylist_yup_inch.dae", dae_l3()), ("nested_nodes.dae", dae_l4()),
                       ("instances.dae", dae_l5())]:
        with open(os.path.join(MESHES, name), "w") as f:
            f.write(text)
    with open(os.path.join(OUT, "mesh_variants.urdf"), "w") as f:
        f.write(URDF.format(joints=joints()))
    with open(os.path.join(OUT, "package.xml"), "w") as f:
        f.write("<package format=\"3\"><name>mesh_variants</name><version>0.0.0</version>"
                "<description>scm test robot</description><maintainer email=\"scm@example.com\">scm</maintainer>"
                "<license>Apache-2.0</license></package>\n")


if __name__ == "__main__":
    main()
