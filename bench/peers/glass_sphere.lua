-- Peer benchmark (docs/PEERS.md): a clear glass sphere on a diffuse floor under a point light; the
-- sphere focuses the light into a bright spot inside its own shadow. glass_sphere.pov is the same
-- scene for POV-Ray 3.7; README.md maps every parameter.

floor_mat = gr.material({0.8, 0.8, 0.8}, {0, 0, 0}, 0)
-- ks = 1: Fresnel splits all of it between reflection and refraction (POV-Ray: reflection
-- {0, 1 fresnel on} with conserve_energy and a filter-1 pigment). kd = 0: colourless.
glass = gr.material({0, 0, 0}, {1, 1, 1}, 120)
glass:set_ri(1.5)

scene = gr.node('scene')

floor = gr.cube('floor')
floor:translate(0, -0.05, 0)
floor:scale(4, 0.05, 4)
floor:set_material(floor_mat)
scene:add_child(floor)

ball = gr.sphere('ball')
ball:translate(0, 0.75, 0)
ball:scale(0.5, 0.5, 0.5)
ball:set_material(glass)
scene:add_child(ball)

-- 1 / (0.5 + 2 d^2): POV-Ray's fade_distance 0.5, fade_power 2 (2 / (1 + (d / 0.5)^2)).
light = gr.light({-1.6, 3.4, -0.8}, {10, 10, 10}, {0.5, 0, 2})

gr.render(scene, 'glass_sphere.png', 512, 512,
          {0, 2.6, 5}, {0.2, -2.2, -5}, {0, 1, 0}, 34,
          {0, 0, 0}, {light})
