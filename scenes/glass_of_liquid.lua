-- A glass of coloured liquid on a table. The glass is a CSG union of the cup (a cylinder minus a
-- thinner one) and the liquid (second operand: it wins where the two overlap, and the union
-- records the glass/liquid interface that refraction uses). The light passing through throws a
-- bright, tinted caustic into the glass's shadow.

table_top = gr.material({0.75, 0.72, 0.66}, {0, 0, 0}, 0)
wall_mat = gr.material({0.55, 0.6, 0.68}, {0, 0, 0}, 0)
glass = gr.material({0, 0, 0}, {0.95, 0.95, 0.95}, 120)
glass:set_ri(1.5)
-- A transparent material's ks is its medium colour (SEED_BEHAVIOUR.md A6): per unit distance light
-- keeps ks of itself, and its reflections are tinted by it too.
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

-- The cup: radius 0.5, wall 0.04 thick, a 0.08 base, 1.3 tall (y from 0 to 1.3).
outer = gr.cylinder('outer')
outer:translate(0, 0.652, 0)
outer:scale(0.5, 0.65, 0.5)
inner = gr.cylinder('inner')
inner:translate(0, 0.8, 0)
inner:scale(0.46, 0.72, 0.46)
cup = gr.difference('cup', outer, inner)
cup:set_material(glass)

-- The liquid fills the cup to 0.8 and reaches a hair into the glass, so the union meets it.
liquid = gr.cylinder('liquid')
liquid:translate(0, 0.44, 0)
liquid:scale(0.465, 0.37, 0.465)
liquid:set_material(wine)

glass_of_wine = gr.union('glass_of_wine', cup, liquid)
glass_of_wine:translate(0.3, 0, 0.2)
scene:add_child(glass_of_wine)

lamp = gr.light({-2.5, 3.0, 1.5}, {1.3, 1.25, 1.2}, {0.3, 0, 0.06})

-- The glass covers about 1% of the lamp's sphere: 2e7 directions trace some 200 000 photons.
gr.option('--caustic-num-photons 20000000 --caustic-num-neighbours 120')
-- The shadow caustic is the point of this scene: the progressive integrator shows it as a bright
-- tinted streak where classic, following the original's roulette, leaves a faint smudge
-- (docs/CAUSTICS.md compares the two). `--integrator classic` on the command line still wins.
gr.option('--integrator progressive')
-- 50.67 degrees across (A7: gr.render's angle is the horizontal one) is 38 degrees from top to bottom.
gr.render(scene, 'glass_of_liquid.png', 640, 480,
          {0.2, 2.4, 5.2}, {0, -0.42, -1}, {0, 1, 0}, 50.67,
          {0.12, 0.12, 0.14}, {lamp})
