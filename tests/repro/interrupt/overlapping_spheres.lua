-- One cancel must stop this render at once: 18 levels of a two-way DAG make 2^18 (262 144)
-- spheres, all within 0.02 of each other, so every camera ray meets every one of them and a
-- packet of 8 rays takes tens of milliseconds, the 16 x 16 tile seconds.
local m = gr.material({0.8,0.2,0.2},{0,0,0},10)
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
local s = gr.sphere('s') s:set_material(m)
local cur = s
for i = 1, 18 do
  local a = gr.node('a' .. i) a:add_child(cur)
  local b = gr.node('b' .. i) b:add_child(cur) b:translate(0.001, 0, 0)
  local n = gr.node('n' .. i) n:add_child(a) n:add_child(b)
  cur = n
end
gr.render(cur, 'x.png', 16, 16, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
