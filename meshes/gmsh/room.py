"""Writes room.msh (ASCII) and room_binary.msh (binary), gmsh MSH 4.1 meshes of a 4 x 2 room
with a round pillar, for harmonic-planner's tests of `hplan plan --mesh-in`.

Physical groups: curves "walls" (tag 1: bottom, top, left), "exit" (tag 2: the right side),
"pillar" (tag 3: the circle); surface "floor" (tag 10).

    pip install gmsh && python3 meshes/gmsh/room.py
"""
import os

import gmsh

here = os.path.dirname(os.path.abspath(__file__))
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("room")
occ = gmsh.model.occ
room = occ.addRectangle(0, 0, 0, 4, 2)
pillar = occ.addDisk(1.5, 1.0, 0, 0.4, 0.4)
floor, _ = occ.cut([(2, room)], [(2, pillar)])
occ.synchronize()
walls, exit_, circle = [], [], []
for dim, tag in gmsh.model.getBoundary(floor, oriented=False):
    x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(dim, tag)
    if x0 > 3.99 and x1 > 3.99:
        exit_.append(tag)
    elif x0 > 0.5 and x1 < 2.5 and y0 > 0.1 and y1 < 1.9:
        circle.append(tag)
    else:
        walls.append(tag)
gmsh.model.addPhysicalGroup(1, walls, 1, name="walls")
gmsh.model.addPhysicalGroup(1, exit_, 2, name="exit")
gmsh.model.addPhysicalGroup(1, circle, 3, name="pillar")
gmsh.model.addPhysicalGroup(2, [t for _, t in floor], 10, name="floor")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.15)
gmsh.model.mesh.generate(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.write(os.path.join(here, "room.msh"))
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write(os.path.join(here, "room_binary.msh"))
gmsh.finalize()
