"""Compiles scm's MuJoCo contact excludes against the robot's URDF with the real MuJoCo.

usage: check_mujoco.py ROBOT.urdf EXCLUDES.xml
Loads the URDF into MuJoCo (geometry stripped: only the body tree and names matter for excludes,
and MuJoCo cannot read every mesh format), saves it as MJCF, adds the excludes file's <contact>
block, compiles, and checks that the model holds exactly the exported excludes. Prints one JSON line.
"""
import json, os, sys, tempfile
import xml.etree.ElementTree as ET
import mujoco

urdf, excludes = sys.argv[1], sys.argv[2]
tree = ET.parse(urdf)
robot = tree.getroot()
for link in robot.findall("link"):
    for tag in ("visual", "collision"):
        for e in link.findall(tag):
            link.remove(e)
# URDF's default axis; MuJoCo's reader insists on the attribute.
for axis in robot.iter("axis"):
    axis.set("xyz", axis.get("xyz", "1 0 0"))
ext = ET.SubElement(robot, "mujoco")
ET.SubElement(ext, "compiler", {"discardvisual": "true", "boundmass": "0.01", "boundinertia": "0.0001"})
with tempfile.TemporaryDirectory() as tmp:
    stripped = os.path.join(tmp, "robot.urdf")
    tree.write(stripped)
    base = mujoco.MjModel.from_xml_path(stripped)
    mjcf = os.path.join(tmp, "robot.xml")
    mujoco.mj_saveLastXML(mjcf, base)
    model_tree = ET.parse(mjcf)
    wanted = [(e.get("body1"), e.get("body2")) for e in ET.parse(excludes).getroot().iter("exclude")]
    contact = ET.parse(excludes).getroot().find("contact")
    model_tree.getroot().append(contact)
    combined = os.path.join(tmp, "combined.xml")
    model_tree.write(combined)
    model = mujoco.MjModel.from_xml_path(combined)
    got = []
    for i in range(model.nexclude):
        b1 = model.body(model.exclude_signature[i] >> 16).name
        b2 = model.body(model.exclude_signature[i] & 0xFFFF).name
        got.append(sorted([b1, b2]))
    print(json.dumps({
        "bodies": [model.body(i).name for i in range(model.nbody)],
        "nexclude": int(model.nexclude),
        "wanted": sorted(sorted(p) for p in wanted),
        "got": sorted(got),
    }))
