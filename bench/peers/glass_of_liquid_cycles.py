# Peer benchmark (docs/PEERS.md): glass_of_liquid.lua for Blender 3.4's Cycles, built from scratch.
#   blender -b --factory-startup --python-exit-code 2 -P glass_of_liquid_cycles.py -- --out PREFIX [options]
# cycles_common.py has the options, the render settings and the mapping of our parameters.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_common as cc  # noqa: E402

args = cc.start()

table = cc.box("table", (-4, -0.1, -3), (4, 0, 3), cc.diffuse("table_top", (0.75, 0.72, 0.66)))
wall = cc.box("wall", (-4, -0.2, -3.05), (4, 4.2, -2.95), cc.diffuse("wall", (0.55, 0.6, 0.68)))

# Our CSG: union(cup, liquid), the liquid (r 0.465, y 0.07 to 0.81) winning where it overlaps the
# cup (r 0.5, y 0.002 to 1.302, minus r 0.46 from y 0.08 up), all moved by (0.3, 0, 0.2). Cycles
# has no CSG and no nested media, so the result is built as its interfaces: the glass's surfaces
# that face air (bottom, outer wall, rim, inner wall above the liquid) and the liquid's closed
# surface, whose index is 1.34 where it faces air and 1.34 / 1.5 where it faces glass.
centre = (0.3, 0, 0.2)
cup = cc.lathe("cup", [(0, 0.002), (0.5, 0.002), (0.5, 1.302), (0.46, 1.302), (0.46, 0.81)], centre,
               cc.glass("glass", 1.5))
# A transparent material's ks is its medium colour: (0.85, 0.25, 0.2) of the light kept per unit.
wine = cc.liquid("wine", 1.34, 1.5, centre, 0.81, 0.4625, (0.85, 0.25, 0.2))
liquid = cc.lathe("liquid", [(0, 0.07), (0.465, 0.07), (0.465, 0.81), (0.46, 0.81), (0, 0.81)], centre, wine)
cc.mark_casters(args, casters=[cup, liquid], receivers=[table, wall])

cc.point_light(args, (-2.5, 3.0, 1.5), (32.5, 31.25, 30), (0.5, 0, 2))
cc.camera((0.2, 2.4, 5.2), (0, -0.42, -1), (0, 1, 0), 38)
cc.render(args)
