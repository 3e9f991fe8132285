-- Constructive solid geometry (seed 1.2): union, intersection and difference, and a union that
-- records medium interfaces (a glass holding a coloured liquid, a glass block with an air bubble).
-- Seed conventions: gr.cube spans [-1,1], gr.cylinder is y in [-1,1] of radius 1; each transform
-- call post-multiplies, so the call written last acts first on the geometry.

red = gr.material({0.8, 0.15, 0.12}, {0.4, 0.4, 0.4}, 40)
blue = gr.material({0.15, 0.3, 0.8}, {0.4, 0.4, 0.4}, 40)
green = gr.material({0.2, 0.65, 0.25}, {0.3, 0.3, 0.3}, 30)
gold = gr.material({0.9, 0.7, 0.2}, {0.3, 0.3, 0.3}, 30)
floor_white = gr.material({0.75, 0.75, 0.72}, {0.0, 0.0, 0.0}, 0)
wall_colour = gr.material({0.55, 0.6, 0.7}, {0.0, 0.0, 0.0}, 0)
glass = gr.material({0.0, 0.0, 0.0}, {0.9, 0.9, 0.9}, 150)
glass:set_ri(1.5)
-- A transparent material's kd is its medium colour: light keeps kd^distance of itself.
juice = gr.material({0.95, 0.45, 0.08}, {0.9, 0.9, 0.9}, 150)
juice:set_ri(1.33)
bubble = gr.air()

scene = gr.node('scene')

floor = gr.cube('floor')
floor:translate(0, -0.05, 0)
floor:scale(12, 0.05, 12)
floor:set_material(floor_white)
scene:add_child(floor)

wall = gr.cube('wall')
wall:translate(0, 3, -4)
wall:scale(12, 3, 0.05)
wall:set_material(wall_colour)
scene:add_child(wall)

-- Stripes on the wall, seen bent through the glass objects.
stripe_colours = {red, gold, green, blue}
for i = 0, 7 do
  local stripe = gr.cube('stripe' .. i)
  stripe:translate(-5.25 + 1.5 * i, 1.6, -3.9)
  stripe:scale(0.3, 1.6, 0.05)
  stripe:set_material(stripe_colours[i % 4 + 1])
  scene:add_child(stripe)
end

-- Back row. Union: a ball through a box.
ub = gr.cube('union_box')
ub:scale(0.6, 0.6, 0.6)
us = gr.sphere('union_ball')
us:translate(0.45, 0.45, 0.45)
us:scale(0.55, 0.55, 0.55)
u = gr.union('union', ub, us)
u:set_material(red)
u:translate(-2.6, 0.85, -2.0)
u:rotate('y', 25)
scene:add_child(u)

-- Intersection: a rounded die (a cube and a ball).
ic = gr.cube('die_cube')
ic:scale(0.7, 0.7, 0.7)
is = gr.sphere('die_ball')
is:scale(0.95, 0.95, 0.95)
die = gr.intersection('die', ic, is)
die:set_material(blue)
die:translate(0, 0.7, -2.0)
die:rotate('y', 30)
scene:add_child(die)

-- Difference: the die with three crossed cylinders drilled out (nested CSG; the drills are
-- one group, an implicit union, and show their own gold material inside the holes).
dc = gr.cube('drilled_cube')
dc:scale(0.7, 0.7, 0.7)
ds = gr.sphere('drilled_ball')
ds:scale(0.95, 0.95, 0.95)
rounded = gr.intersection('rounded', dc, ds)
drills = gr.node('drills')
drills:set_material(gold)
for axis, name in ipairs({'x', 'y', 'z'}) do
  local c = gr.cylinder('drill_' .. name)
  if name == 'x' then c:rotate('z', 90) end
  if name == 'z' then c:rotate('x', 90) end
  c:scale(0.38, 1.2, 0.38)
  drills:add_child(c)
end
drilled = gr.difference('drilled', rounded, drills)
drilled:set_material(green)
drilled:translate(2.6, 0.75, -2.0)
drilled:rotate('y', -30)
drilled:rotate('x', 20)
scene:add_child(drilled)

-- Front row. A cup: a cylinder minus a narrower one that starts above the bottom.
local function cup(name)
  local outer = gr.cylinder(name .. '_outer')
  outer:scale(0.6, 0.7, 0.6)
  local inner = gr.cylinder(name .. '_inner')
  inner:translate(0, 0.15, 0)
  inner:scale(0.52, 0.75, 0.52)
  local c = gr.difference(name, outer, inner)
  c:set_material(glass)
  return c
end

empty_cup = cup('empty_cup')
empty_cup:translate(-2.3, 0.702, 1.0)  -- a hair above the floor: no coincident faces
scene:add_child(empty_cup)

-- A glass of juice: union(cup, juice). The juice is the second operand, so it wins where the
-- two overlap (it reaches slightly into the glass) and the union records the glass/juice
-- interface that refraction uses.
juice_body = gr.cylinder('juice')
juice_body:translate(0, -0.18, 0)
juice_body:scale(0.525, 0.43, 0.525)
juice_body:set_material(juice)
full_glass = gr.union('glass_of_juice', cup('juice_cup'), juice_body)
full_glass:translate(0, 0.702, 1.3)
scene:add_child(full_glass)

-- A glass block with an air bubble: union(glass, air) makes a glass/air interface inside.
block = gr.cube('block')
block:scale(0.55, 0.55, 0.55)
block:set_material(glass)
air_ball = gr.sphere('bubble')
air_ball:scale(0.38, 0.38, 0.38)
air_ball:set_material(bubble)
paperweight = gr.union('paperweight', block, air_ball)
paperweight:translate(2.3, 0.552, 1.0)
paperweight:rotate('y', 20)
scene:add_child(paperweight)

light = gr.light({4.0, 9.0, 7.0}, {0.95, 0.95, 0.9}, {0.7, 0, 0.0025})

-- gr.render's angle is the horizontal one (SEED_BEHAVIOUR.md A7): 60.8 across a 16:10 image.
gr.render(scene, 'csg_showcase.png', 640, 400,
          {0, 4.4, 8.5}, {0, -3.7, -8.5}, {0, 1, 0}, 60.8,
          {0.3, 0.3, 0.3}, {light})
