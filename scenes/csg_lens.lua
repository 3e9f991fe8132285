-- A biconvex glass lens made by constructive solid geometry: the intersection of two spheres
-- (seed 1.2). It stands in front of coloured bars topped by balls, which it shows upside down
-- and mirrored (they are beyond its focal length, f = R / (2 (n - 1)) = 2). Its light has a
-- quadratic falloff, so --caustic-num-photons N also shows it focusing light on the floor.
-- Seed conventions: gr.cube spans [-1,1]; each transform call post-multiplies, so the call
-- written last acts first on the geometry.

glass = gr.material({0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, 120)
glass:set_ri(1.5)
white = gr.material({0.8, 0.8, 0.78}, {0.0, 0.0, 0.0}, 0)
floor_grey = gr.material({0.55, 0.55, 0.6}, {0.0, 0.0, 0.0}, 0)
colours = {
  gr.material({0.85, 0.15, 0.1}, {0.0, 0.0, 0.0}, 0),
  gr.material({0.95, 0.55, 0.1}, {0.0, 0.0, 0.0}, 0),
  gr.material({0.9, 0.85, 0.15}, {0.0, 0.0, 0.0}, 0),
  gr.material({0.2, 0.7, 0.25}, {0.0, 0.0, 0.0}, 0),
  gr.material({0.15, 0.4, 0.85}, {0.0, 0.0, 0.0}, 0),
  gr.material({0.55, 0.2, 0.75}, {0.0, 0.0, 0.0}, 0),
}

scene = gr.node('scene')

floor = gr.cube('floor')
floor:translate(0, -2.05, 0)
floor:scale(8, 0.05, 8)
floor:set_material(floor_grey)
scene:add_child(floor)

wall = gr.cube('wall')
wall:translate(0, 1.5, -4.1)
wall:scale(8, 3.6, 0.05)
wall:set_material(white)
scene:add_child(wall)

-- Six vertical bars on the wall, each with a ball on top (so up and down are easy to tell).
for i, colour in ipairs(colours) do
  local x = -4.375 + 1.25 * i
  local bar = gr.cube('bar' .. i)
  bar:translate(x, 0.4, -4.0)
  bar:scale(0.35, 1.1, 0.05)
  bar:set_material(colour)
  scene:add_child(bar)
  local ball = gr.sphere('ball' .. i)
  ball:translate(x, 1.95, -3.6)
  ball:scale(0.4, 0.4, 0.4)
  ball:set_material(colour)
  scene:add_child(ball)
end

-- The lens: two spheres of radius 2 whose centres are 3.2 apart; it is 0.8 thick at the
-- centre, with a rim of radius 1.2.
front = gr.sphere('front_face')
front:translate(0, 0, -1.6)
front:scale(2, 2, 2)
back = gr.sphere('back_face')
back:translate(0, 0, 1.6)
back:scale(2, 2, 2)
lens = gr.intersection('lens', front, back)
lens:set_material(glass)
lens:translate(0, 0.3, 2.0)
lens:rotate('y', 15)
scene:add_child(lens)

-- A foot for the lens to stand on.
stand = gr.cylinder('stand')
stand:translate(0, -1.5, 2.0)
stand:scale(0.08, 0.55, 0.08)
stand:set_material(white)
scene:add_child(stand)

light = gr.light({3.0, 6.0, 7.0}, {0.9, 0.9, 0.9}, {0.8, 0, 0.002})
-- The lens covers 0.5% of the light's sphere: 3e7 directions trace about 150 000 photons.
gr.option('--caustic-num-photons 30000000')
-- The focus on the floor is the point: progressive shows it bright and round where classic's
-- roulette dims it (docs/CAUSTICS.md). `--integrator classic` on the command line still wins.
gr.option('--integrator progressive')

gr.render(scene, 'csg_lens.png', 512, 512,
          {0, 0.6, 8.5}, {0, -0.05, -1}, {0, 1, 0}, 45,
          {0.3, 0.3, 0.3}, {light})
