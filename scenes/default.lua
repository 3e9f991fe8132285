-- caustica's default scene: a Cornell box with a glass sphere, a mirror sphere and a metal ring.
-- Seed conventions: gr.cube spans [-1,1]; each transform call post-multiplies, so the call
-- written last acts first on the geometry.

white = gr.material({0.75, 0.75, 0.75}, {0.0, 0.0, 0.0}, 0)
red   = gr.material({0.75, 0.15, 0.12}, {0.0, 0.0, 0.0}, 0)
green = gr.material({0.15, 0.6, 0.2}, {0.0, 0.0, 0.0}, 0)
glass = gr.material({0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, 80)
glass:set_ri(1.5)
mirror = gr.material({0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, 80)
mirror:set_reflective()
gold = gr.material({0.05, 0.04, 0.0}, {0.85, 0.7, 0.3}, 60)
gold:set_reflective()

scene = gr.node('scene')

-- The box: five walls, 4 units wide, open towards the camera.
local function wall(name, material, tx, ty, tz, sx, sy, sz)
  local w = gr.cube(name)
  w:translate(tx, ty, tz)
  w:scale(sx, sy, sz)
  w:set_material(material)
  scene:add_child(w)
  return w
end
wall('floor',   white, 0, -2.05, 0, 2.1, 0.05, 2.1)
wall('ceiling', white, 0,  2.05, 0, 2.1, 0.05, 2.1)
wall('back',    white, 0, 0, -2.05, 2.1, 2.1, 0.05)
wall('left',    red,  -2.05, 0, 0, 0.05, 2.1, 2.1)
wall('right',   green, 2.05, 0, 0, 0.05, 2.1, 2.1)

glass_ball = gr.sphere('glass_ball')
glass_ball:translate(-0.85, -1.298, 0.3)
glass_ball:scale(0.7, 0.7, 0.7)
glass_ball:set_material(glass)
scene:add_child(glass_ball)

mirror_ball = gr.sphere('mirror_ball')
mirror_ball:translate(0.75, -1.4, -1.0)
mirror_ball:scale(0.6, 0.6, 0.6)
mirror_ball:set_material(mirror)
scene:add_child(mirror_ball)

-- A metal ring: a cylinder minus a slightly thinner, taller one. Light falling on its inner
-- wall is focused into a cardioid on the floor inside it.
ring_outer = gr.cylinder('ring_outer')
ring_outer:scale(0.62, 0.15, 0.62)
ring_inner = gr.cylinder('ring_inner')
ring_inner:scale(0.58, 0.2, 0.58)
ring = gr.difference('ring', ring_outer, ring_inner)
ring:translate(0.95, -1.848, 0.85)
ring:set_material(gold)
scene:add_child(ring)

-- Caustics need a light with quadratic falloff (c2 > 0): photon energies follow it.
light = gr.light({-1.1, 0.5, 1.8}, {1.6, 1.6, 1.5}, {0.2, 0, 0.15})
-- The preview preset (10^7 photon directions, N = 25: the knee of the error/time curves in
-- docs/ACCURACY.md); `caustica render --quality final scenes/default.lua` for a final image.
gr.option('--quality preview')

gr.render(scene, 'default.png', 512, 512,
          {0, 0.9, 7.5}, {0, -0.17, -1}, {0, 1, 0}, 40,
          {0.15, 0.15, 0.15}, {light})
