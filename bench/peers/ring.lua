-- Peer benchmark (docs/PEERS.md): a metal ring, the CSG difference of two cylinders, on a diffuse
-- floor under a point light low on its left; light reflected by the inner wall draws a cardioid on
-- the floor inside.
-- ring.pov is the same scene for POV-Ray 3.7; README.md maps every parameter.

floor_mat = gr.material({0.8, 0.8, 0.8}, {0, 0, 0}, 0)
-- A pure gold-coloured mirror (no diffuse term): POV-Ray reflection rgb <0.9, 0.75, 0.4>.
gold = gr.material({0, 0, 0}, {0.9, 0.75, 0.4}, 60)
gold:set_reflective()

scene = gr.node('scene')

floor = gr.cube('floor')
floor:translate(0, -0.05, 0)
floor:scale(4, 0.05, 4)
floor:set_material(floor_mat)
scene:add_child(floor)

-- Radius 1, wall 0.05 thick, 0.35 tall, a hair above the floor (y from 0.002 to 0.352).
outer = gr.cylinder('outer')
outer:scale(1, 0.175, 1)
inner = gr.cylinder('inner')
inner:scale(0.95, 0.3, 0.95)
ring = gr.difference('ring', outer, inner)
ring:translate(0, 0.177, 0)
ring:set_material(gold)
scene:add_child(ring)

-- Low on the left (29 degrees above the floor): 1 / (0.5 + 2 d^2) is POV-Ray's fade_distance 0.5, fade_power 2.
light = gr.light({-4, 2.2, 0}, {12, 12, 12}, {0.5, 0, 2})

gr.render(scene, 'ring.png', 512, 512,
          {0, 4.2, 2.2}, {0, -4.2, -2.2}, {0, 1, 0}, 36,
          {0, 0, 0}, {light})
