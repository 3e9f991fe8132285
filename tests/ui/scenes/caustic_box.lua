-- Preview test scene: a glass ball and a mirror post on a floor before a wall, lit by one light
-- with quadratic falloff (so it shoots caustic photons). Small, so that tests render it quickly.
white  = gr.material({0.7, 0.7, 0.7}, {0.0, 0.0, 0.0}, 0)
blue   = gr.material({0.25, 0.35, 0.7}, {0.0, 0.0, 0.0}, 0)
glass  = gr.material({0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, 60)
glass:set_ri(1.5)
mirror = gr.material({0.0, 0.0, 0.0}, {0.85, 0.85, 0.85}, 60)
mirror:set_reflective()

root = gr.node('root')

floor = gr.cube('floor')
floor:translate(0, -1.05, 0)
floor:scale(3, 0.05, 3)
floor:set_material(white)
root:add_child(floor)

wall = gr.cube('wall')
wall:translate(0, 0.5, -2.5)
wall:scale(3, 1.6, 0.05)
wall:set_material(blue)
root:add_child(wall)

ball = gr.sphere('ball')
ball:translate(-0.6, -0.45, 0)
ball:scale(0.55, 0.55, 0.55)
ball:set_material(glass)
root:add_child(ball)

post = gr.cylinder('post')
post:translate(0.8, -0.6, -0.4)
post:scale(0.3, 0.4, 0.3)
post:set_material(mirror)
root:add_child(post)

light = gr.light({0.3, 2.2, 0.8}, {4.0, 4.0, 3.8}, {0.3, 0.0, 0.45})
gr.option('--caustic-num-photons 2000000')

-- The angle is the horizontal one (docs/SCENE_LANGUAGE.md, "camera angle"): 60 across 256 x 192 is
-- 45 vertically, the framing the tests measure (the sky shows past the wall's top corners).
gr.render(root, 'caustic_box.png', 256, 192,
          {0, 1.6, 4.6}, {0, -0.4, -1}, {0, 1, 0}, 60,
          {0.2, 0.2, 0.2}, {light})
