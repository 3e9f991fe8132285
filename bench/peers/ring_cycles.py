# Peer benchmark (docs/PEERS.md): ring.lua for Blender 3.4's Cycles, built from scratch.
#   blender -b --factory-startup --python-exit-code 2 -P ring_cycles.py -- --out PREFIX [options]
# cycles_common.py has the options, the render settings and the mapping of our parameters.
# MNEE follows refraction only: with the ring a caustic caster (--mode mnee), Cycles also culls
# the paths that reach the lamp off it from the floor, so the cardioid is missing from that render.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_common as cc  # noqa: E402

args = cc.start()

floor = cc.box("floor", (-4, -0.1, -4), (4, 0, 4), cc.diffuse("floor", (0.8, 0.8, 0.8)))
# gr.difference of the cylinders r 1 (y 0.002 to 0.352) and r 0.95 (cutting through): a tube,
# its profile walked up the outer wall, in across the top, down the inner wall, out across the
# bottom.
ring = cc.lathe("ring", [(1, 0.002), (1, 0.352), (0.95, 0.352), (0.95, 0.002), (1, 0.002)], (0, 0, 0),
                cc.mirror("gold", (0.9, 0.75, 0.4)))
cc.mark_casters(args, casters=[ring], receivers=[floor])

cc.point_light(args, (-4, 2.2, 0), (12, 12, 12), (0.5, 0, 2))
cc.camera((0, 4.2, 2.2), (0, -4.2, -2.2), (0, 1, 0), 36)
cc.render(args)
