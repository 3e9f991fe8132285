-- Peer benchmark (docs/PEERS.md): a glass of red liquid on a table, as scenes/glass_of_liquid.lua
-- but square, without ambient light, with ks = 1 and POV-Ray-compatible light falloff. The glass is
-- a CSG union of the cup (a cylinder minus a thinner one) and the liquid (the second operand: it
-- wins where the two overlap). glass_of_liquid.pov is the same scene for POV-Ray 3.7; README.md
-- maps every parameter.

table_top = gr.material({0.75, 0.72, 0.66}, {0, 0, 0}, 0)
wall_mat = gr.material({0.55, 0.6, 0.68}, {0, 0, 0}, 0)
glass = gr.material({0, 0, 0}, {1, 1, 1}, 120)
glass:set_ri(1.5)
-- A transparent material's ks is its medium colour (docs/SCENE_LANGUAGE.md): per unit distance
-- light keeps ks of itself, and its reflections are tinted by it too.
-- (POV-Ray: fade_power 1001, fade_distance 1 / ln 5, fade_color 1 + ln(kd) / ln 5).
wine = gr.material({0, 0, 0}, {0.85, 0.25, 0.2}, 120)
wine:set_ri(1.34)

scene = gr.node('scene')

tabletop = gr.cube('table')
tabletop:translate(0, -0.05, 0)
tabletop:scale(4, 0.05, 3)
tabletop:set_material(table_top)
scene:add_child(tabletop)

wall = gr.cube('wall')
wall:translate(0, 2, -3)
wall:scale(4, 2.2, 0.05)
wall:set_material(wall_mat)
scene:add_child(wall)

-- The cup: radius 0.5, wall 0.04 thick, a 0.08 base, 1.3 tall (y from 0.002 to 1.302).
outer = gr.cylinder('outer')
outer:translate(0, 0.652, 0)
outer:scale(0.5, 0.65, 0.5)
inner = gr.cylinder('inner')
inner:translate(0, 0.8, 0)
inner:scale(0.46, 0.72, 0.46)
cup = gr.difference('cup', outer, inner)
cup:set_material(glass)

-- The liquid fills the cup to 0.81 and reaches a hair into the glass, so the union meets it.
liquid = gr.cylinder('liquid')
liquid:translate(0, 0.44, 0)
liquid:scale(0.465, 0.37, 0.465)
liquid:set_material(wine)

glass_of_wine = gr.union('glass_of_wine', cup, liquid)
glass_of_wine:translate(0.3, 0, 0.2)
scene:add_child(glass_of_wine)

-- 1 / (0.5 + 2 d^2): POV-Ray's fade_distance 0.5, fade_power 2.
lamp = gr.light({-2.5, 3.0, 1.5}, {32.5, 31.25, 30}, {0.5, 0, 2})

gr.render(scene, 'glass_of_liquid.png', 512, 512,
          {0.2, 2.4, 5.2}, {0, -0.42, -1}, {0, 1, 0}, 38,
          {0, 0, 0}, {lamp})
