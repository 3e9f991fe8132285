local N = 30000
local m = gr.material({0.8,0.2,0.2},{0,0,0},10)
local s = gr.sphere('s'); s:set_material(m)
local cur = s
for i = 1, N do local t = gr.sphere('t'); t:set_material(m); cur = gr.union(cur, t) end
local root = gr.node('root'); root:add_child(cur)
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
gr.render(root, 'x.png', 32, 32, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
