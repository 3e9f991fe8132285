local N = 30000
local root = gr.node('root')
local cur = root
for i = 1, N do local n = gr.node('n'); cur:add_child(n); cur = n end
local s = gr.sphere('s'); s:set_material(gr.material({0.8,0.2,0.2},{0,0,0},10)); cur:add_child(s)
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
gr.render(root, 'x.png', 32, 32, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
