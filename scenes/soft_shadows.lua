-- Soft shadows from spherical lights: the penumbra widens with the light's radius and with the
-- distance from the blocker to the surface. Try --no-soft-shadows and --shadow-grid 8.

floor_mat = gr.material({0.8, 0.78, 0.72}, {0, 0, 0}, 0)
blue = gr.material({0.2, 0.35, 0.8}, {0.4, 0.4, 0.4}, 40)
orange = gr.material({0.9, 0.45, 0.1}, {0.3, 0.3, 0.3}, 20)
grey = gr.material({0.5, 0.5, 0.5}, {0.2, 0.2, 0.2}, 10)

scene = gr.node('scene')

floor = gr.cube('floor')
floor:translate(0, -1.05, 0)
floor:scale(6, 0.05, 6)
floor:set_material(floor_mat)
scene:add_child(floor)

-- A post whose shadow shows the penumbra growing with distance along it.
post = gr.cylinder('post')
post:translate(-1.5, 0.0, 0)
post:scale(0.12, 1.0, 0.12)
post:set_material(grey)
scene:add_child(post)

ball = gr.sphere('ball')
ball:translate(0.4, -0.4, 0.6)
ball:scale(0.6, 0.6, 0.6)
ball:set_material(blue)
scene:add_child(ball)

-- A floating cube: its shadow is soft all round.
cube = gr.cube('cube')
cube:translate(1.8, 0.3, -0.8)
cube:rotate('y', 30)
cube:scale(0.35, 0.35, 0.35)
cube:set_material(orange)
scene:add_child(cube)

lamp = gr.light({-2.0, 3.5, 2.0}, {0.9, 0.88, 0.8}, {1, 0, 0})
lamp:set_radius(0.6)

gr.option('--shadow-grid 6')
-- gr.render's angle is the horizontal one (SEED_BEHAVIOUR.md A7): 72 across a 16:10 image.
gr.render(scene, 'soft_shadows.png', 640, 400,
          {0, 2.2, 6}, {0, -0.35, -1}, {0, 1, 0}, 72,
          {0.15, 0.15, 0.17}, {lamp})
