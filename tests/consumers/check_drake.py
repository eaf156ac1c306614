"""Loads scm's Drake collision filter groups with the real Drake and reports the filtered link pairs.

usage: check_drake.py ROBOT.urdf FILTERS.xml
Every link with collision geometry gets a small sphere instead (Drake does not read every mesh format;
filters act on bodies, not shapes); the filter groups are pasted inside <robot>. Prints one JSON line:
the filtered link pairs with the groups and without them (Drake's own filters: joined or welded).
"""
import json, logging, sys
import xml.etree.ElementTree as ET
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.systems.framework import DiagramBuilder

DRAKE = "http://drake.mit.edu"
logging.getLogger("drake").setLevel(logging.ERROR)
urdf, filters = sys.argv[1], sys.argv[2]


def filtered_pairs(with_groups):
    ET.register_namespace("drake", DRAKE)
    tree = ET.parse(urdf)
    robot = tree.getroot()
    for link in robot.findall("link"):
        had = link.findall("collision")
        for tag in ("visual", "collision"):
            for e in link.findall(tag):
                link.remove(e)
        if had:
            c = ET.SubElement(link, "collision")
            g = ET.SubElement(c, "geometry")
            ET.SubElement(g, "sphere", {"radius": "0.01"})
    for axis in robot.iter("axis"):
        axis.set("xyz", axis.get("xyz", "1 0 0"))
    text = ET.tostring(robot, encoding="unicode")
    if with_groups:
        groups = open(filters).read()
        if 'xmlns:drake' not in text.split(">", 1)[0]:
            text = text.replace("<robot ", f'<robot xmlns:drake="{DRAKE}" ', 1)
        text = text[: text.rindex("</robot>")] + groups + "</robot>\n"
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, 0.0)
    models = Parser(plant).AddModelsFromString(text, "urdf")
    plant.Finalize()
    inspector = scene_graph.model_inspector()
    geoms = []
    for model in models:
        for index in plant.GetBodyIndices(model):
            body = plant.get_body(index)
            for g in plant.GetCollisionGeometriesForBody(body):
                geoms.append((body.name(), g))
    out = set()
    for i in range(len(geoms)):
        for j in range(i + 1, len(geoms)):
            (a, ga), (b, gb) = geoms[i], geoms[j]
            if a != b and inspector.CollisionFiltered(ga, gb):
                out.add(tuple(sorted((a, b))))
    return sorted(out)


print(json.dumps({"with": filtered_pairs(True), "without": filtered_pairs(False)}))
