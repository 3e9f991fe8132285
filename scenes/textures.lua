-- Textures and bump maps on every primitive kind (docs/TEXTURES.md has the rules).
-- The images come from textures/make_textures.py.
-- Seed conventions: gr.cube spans [-1,1]; each transform call post-multiplies, so the call
-- written last acts first on the geometry.

local textures = 'textures/'

scene = gr.node('scene')

local function add(node, material, tx, ty, tz, sx, sy, sz)
  node:translate(tx, ty, tz)
  node:scale(sx, sy, sz)
  node:set_material(material)
  scene:add_child(node)
  return node
end

-- Floor: pale stone with concentric ripples (sinewaves) over its whole top face.
floor_stone = gr.material({0.55, 0.6, 0.65}, {0.35, 0.35, 0.35}, 40)
ripples = gr.bumpmap('sinewaves')
ripples:remap('cubetop')
floor_stone:set_bumpmap(ripples)
add(gr.cube('floor'), floor_stone, 0, -1.1, 0, 8, 0.1, 8)

-- Back wall: four brick panels, each showing the whole brick image on its front face,
-- with the matching height map for the mortar grooves.
brick = gr.material({0.6, 0.3, 0.2}, {0.0, 0.0, 0.0}, 0)
brick_colour = gr.texture(textures .. 'bricks.png')
brick_colour:remapt('cubefront')
brick_relief = gr.bumpmap(textures .. 'bricks_bump.png')
brick_relief:remap('cubefront')
brick:set_texture(brick_colour)
brick:set_bumpmap(brick_relief)
for i = 0, 3 do
  add(gr.cube('wall' .. i), brick, -6 + 4 * i, 1, -5, 2, 2, 0.2)
end

-- A die: the cube's own uv, a 4 x 3 cross wrapped around z (no remap). The camera sees the
-- top (+y, 1), the front (+z, 2) and the -x face (4); the dark bar on each side face hugs the top.
die_faces = gr.material({1, 1, 1}, {0.2, 0.2, 0.2}, 30)
die_faces:set_texture(gr.texture(textures .. 'die_unwrap.png'))
die = gr.cube('die')
die:translate(-3.3, 0, 1.6)
die:rotate('y', 35)
die:set_material(die_faces)
scene:add_child(die)

-- A planet: a map for the sphere's uv (centre column at +x, seam at -x, rows linear in height),
-- its axis tilted.
planet = gr.material({1, 1, 1}, {0.15, 0.15, 0.15}, 20)
planet:set_texture(gr.texture(textures .. 'globe.png'))
globe = gr.sphere('globe')
globe:translate(0, 0.2, -0.5)
globe:rotate('z', -20)
globe:rotate('y', 30)
globe:scale(1.2, 1.2, 1.2)
globe:set_material(planet)
scene:add_child(globe)

-- A drum: a compass rose on the cylinder's top cap (cyltop), north towards -z. Outside the
-- window (the side, in the lower half of the cylinder's uv) the texture gives black: a black
-- lacquered side with brass-coloured highlights.
drum = gr.material({0.7, 0.55, 0.25}, {0.5, 0.42, 0.25}, 25)
compass = gr.texture(textures .. 'compass.png')
compass:remapt('cyltop')
drum:set_texture(compass)
add(gr.cylinder('drum'), drum, 2.6, -0.45, -1.6, 1.1, 0.55, 1.1)

-- A spinning top: a cone (height 1, base radius 1) turned over onto its apex, scaled to height
-- 1.6, with a colour wheel on its flat base, now facing up (conetop). The side is outside the
-- window: black, with highlights.
wheel = gr.material({1, 1, 1}, {0.4, 0.4, 0.4}, 40)
wheel_texture = gr.texture(textures .. 'colour_wheel.png')
wheel_texture:remapt('conetop')
wheel:set_texture(wheel_texture)
spinning_top = gr.cone('spinning_top')
spinning_top:translate(-2.3, -0.2, -2.6)
spinning_top:rotate('x', 180)
spinning_top:scale(1.0, 1.6, 1.0)
spinning_top:set_material(wheel)
scene:add_child(spinning_top)

-- A checkerboard ball (redcheck: 24 squares per uv unit, so 24 around and 24 from pole to pole).
checks = gr.material({1, 1, 1}, {0.3, 0.3, 0.3}, 50)
checks:set_texture(gr.texture('redcheck'))
add(gr.sphere('checker_ball'), checks, 2.9, -0.3, 1.6, 0.7, 0.7, 0.7)

key = gr.light({-5, 9, 8}, {0.85, 0.85, 0.85}, {1, 0, 0})
key:set_radius(0.6)
fill = gr.light({7, 4, 6}, {0.25, 0.25, 0.3}, {1, 0, 0})

gr.set_miss_colour({0.08, 0.1, 0.15})
-- gr.render's angle is the horizontal one (SEED_BEHAVIOUR.md A7): 72 across a 16:10 image.
gr.render(scene, 'textures.png', 640, 400,
          {0, 4.5, 10.5}, {0, -4.8, -10.5}, {0, 1, 0}, 72,
          {0.2, 0.2, 0.2}, {key, fill})
