# Peer benchmark (docs/PEERS.md): glass_sphere.lua for Blender 3.4's Cycles, built from scratch.
#   blender -b --factory-startup --python-exit-code 2 -P glass_sphere_cycles.py -- --out PREFIX [options]
# cycles_common.py has the options, the render settings and the mapping of our parameters.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_common as cc  # noqa: E402

args = cc.start()

floor = cc.box("floor", (-4, -0.1, -4), (4, 0, 4), cc.diffuse("floor", (0.8, 0.8, 0.8)))
# gr.sphere translate(0, 0.75, 0) scale(0.5): index 1.5, ks = 1.
ball = cc.sphere("ball", (0, 0.75, 0), 0.5, cc.glass("glass", 1.5))
cc.mark_casters(args, casters=[ball], receivers=[floor])

cc.point_light(args, (-1.6, 3.4, -0.8), (10, 10, 10), (0.5, 0, 2))
cc.camera((0, 2.6, 5), (0.2, -2.2, -5), (0, 1, 0), 34)
cc.render(args)
